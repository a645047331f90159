package dev.motionfusion.app

import android.app.Application
import android.content.pm.ApplicationInfo
import dev.motionfusion.app.platform.MainThreadPolicy
import com.google.android.material.color.DynamicColors
import dev.motionfusion.app.calibration.CalibrationDependencies
import dev.motionfusion.app.record.RecordingDependencies
import dev.motionfusion.app.sessions.SessionsDependencies
import dev.motionfusion.app.settings.SettingsRepository
import dev.motionfusion.app.stream.StreamDependencies

/**
 * The application: owns the object graph ([AppGraph]), turns StrictMode on for the main thread
 * in debug builds (violations logged; every Robolectric test makes them fail, `StrictTestApp`)
 * and applies Material You colours from the wallpaper on Android 12+ (the theme's own colours
 * before).
 */
internal open class MotionFusionApp :
    Application(), RecordingDependencies.Provider, SessionsDependencies.Provider, SettingsRepository.Provider, CalibrationDependencies.Provider, StreamDependencies.Provider {
    private var built: AppGraph? = null

    /** The graph; built on first use. Tests set one built with fakes before the first screen starts. */
    var graph: AppGraph
        get() = built ?: AppGraph.create(this).also { built = it }
        set(value) {
            built = value
        }

    override fun onCreate() {
        super.onCreate()
        installMainThreadPolicy()
        DynamicColors.applyToActivitiesIfAvailable(this)
    }

    /** Debug builds: StrictMode logs disk and network work on the main thread. */
    protected open fun installMainThreadPolicy() {
        if (applicationInfo.flags and ApplicationInfo.FLAG_DEBUGGABLE != 0) MainThreadPolicy.install(fail = false)
    }

    override val recordingDependencies: RecordingDependencies get() = graph
    override val sessionsDependencies: SessionsDependencies get() = graph
    override val settingsRepository: SettingsRepository get() = graph.settingsRepository
    override val calibrationDependencies: CalibrationDependencies get() = graph
    override val streamDependencies: StreamDependencies get() = graph
}
