package dev.motionfusion.app

import android.hardware.SensorManager
import dev.motionfusion.app.fusion.EffectiveMode
import dev.motionfusion.app.fusion.FusionMode
import dev.motionfusion.app.fusion.FusionState
import dev.motionfusion.app.live.LiveScreen
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.fusion.ModeReason
import dev.motionfusion.app.fusion.SensorStats
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.ui.PlotMarker
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import kotlin.math.sin

/** Live-screen states made by hand, for the screens' tests: a phone swayed in the hand, its sensors' figures. */
internal object LiveStates {
    private fun stats(rate: Double, accuracy: Int, x: Float, y: Float, z: Float, w: Float = Float.NaN) =
        SensorStats(samples = 3000, rateHz = rate, jitterMs = 0.21, duplicates = 0, backwards = 0, accuracy = accuracy, x = x, y = y, z = z, w = w)

    /** The orientation at [t] s of a phone held in the hand and swayed: heading about 40°, pitch and roll a few tens of degrees. */
    fun swaying(t: Double): Quaternion =
        Quaternion.fromAxisAngle(Vector3.UNIT_Z, Math.toRadians(-40.0 - 25.0 * sin(0.5 * t))) *
            Quaternion.fromAxisAngle(Vector3.UNIT_X, Math.toRadians(35.0 + 20.0 * sin(0.8 * t))) *
            Quaternion.fromAxisAngle(Vector3(0.0, 1.0, 0.0), Math.toRadians(-15.0 + 12.0 * sin(1.1 * t)))

    fun state(
        tNs: Long,
        q: Quaternion?,
        rv: Quaternion?,
        mode: EffectiveMode = EffectiveMode(FusionMode.MARG, ModeReason.AS_CHOSEN),
        magAccuracy: Int = SensorManager.SENSOR_STATUS_ACCURACY_HIGH,
        fieldUt: Double? = 47.3,
        disturbed: Boolean = false,
    ): FusionState {
        val sensors = HashMap<SensorKind, SensorStats>()
        sensors[SensorKind.ACCELEROMETER] = stats(200.1, 3, 1.52f, 5.61f, 7.84f)
        sensors[SensorKind.GYROSCOPE] = stats(200.0, 3, 0.012f, -0.031f, 0.004f)
        if (mode.mode.hasMagneticHeading) sensors[SensorKind.MAGNETOMETER] = stats(100.0, magAccuracy, 12.4f, 28.9f, -34.2f)
        if (rv != null) sensors[SensorKind.ROTATION_VECTOR] = stats(100.0, 3, rv.x.toFloat(), rv.y.toFloat(), rv.z.toFloat(), rv.w.toFloat())
        return FusionState(
            mode = mode, settings = LiveSettings(), orientation = q, rotationVector = rv,
            rotationVectorHeadingAccuracyRad = rv?.let { Math.toRadians(4.0) }, gameRotationVector = null,
            sensors = sensors, magneticFieldUt = if (mode.mode.hasMagneticHeading) fieldUt else null,
            atRest = false, magneticDisturbance = disturbed, accelerometerRejected = false,
            gyroBiasRadS = doubleArrayOf(0.0012, -0.0004, 0.0007), filterSteps = 2400, timestampNs = tNs,
        )
    }

    /** 12 s of swaying at 60 frames/s shown on [screen], the rotation vector 3° off in heading ([ghost]); [last] makes the last frame's state. */
    fun sway(
        screen: LiveScreen,
        markers: List<PlotMarker> = emptyList(),
        ghost: Boolean = true,
        last: (Long, Quaternion, Quaternion?) -> FusionState = { t, q, rv -> state(t, q, rv) },
        frames: Int = 720,
    ) {
        val t0 = 1_000_000_000L
        for (frame in 0..frames) {
            val t = frame / 60.0
            val q = swaying(t)
            val rv = if (ghost) Quaternion.fromAxisAngle(Vector3.UNIT_Z, Math.toRadians(-3.0)) * swaying(t - 0.15) else null
            val tNs = t0 + (t * 1e9).toLong()
            screen.show(if (frame == frames) last(tNs, q, rv) else state(tNs, q, rv), 0, markers)
        }
    }
}
