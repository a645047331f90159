package dev.motionfusion.app.calibration

import android.content.Context
import android.hardware.SensorManager
import dev.motionfusion.core.calib.CalibrationSettings
import kotlinx.coroutines.CoroutineDispatcher
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob

/**
 * What the calibration screen is built from; tests replace members and call [reset].
 *
 * [source] is the one place that decides where the readings come from: to move the screen onto
 * the app's shared capture path, replace its default with an adapter of that path that
 * delivers the streams of [SensorManagerSampleSource] (accelerometer, uncalibrated gyroscope and
 * magnetometer when the device has them) as [CalibrationSample]s.
 */
internal object CalibrationDeps {
    val defaultSource: (Context) -> CalibrationSampleSource = { SensorManagerSampleSource(it.getSystemService(SensorManager::class.java)) }

    @Volatile var source: (Context) -> CalibrationSampleSource = defaultSource
    @Volatile var compute: CoroutineDispatcher = Dispatchers.Default
    @Volatile var io: CoroutineDispatcher = Dispatchers.IO

    /** The fits' settings on the phone: the defaults of `fusion calibrate`, fewer kept magnetometer readings (a few minutes at 100 Hz). */
    val settings = CalibrationSettings(maxMagSamples = 20_000)

    fun reset() {
        source = defaultSource
        compute = Dispatchers.Default
        io = Dispatchers.IO
    }
}

/** The application's [CalibrationStore] (one per process; the recorder and the live filter read it). */
object CalibrationStores {
    private var store: CalibrationStore? = null
    private var owner: Context? = null

    /** The store of [context]'s application, keyed by this device and its sensors. */
    @Synchronized
    fun get(context: Context): CalibrationStore {
        val app = context.applicationContext
        store?.let { if (owner === app) return it }
        // A new Application (only in tests, where each test has its own): start afresh.
        val sensors = SensorManagerSampleSource(app.getSystemService(SensorManager::class.java)).sensorDescriptions()
        val s = CalibrationStore(
            java.io.File(app.filesDir, "calibration"), DeviceKey.thisDevice(sensors),
            app.getSharedPreferences(CalibrationStore.PREFS, Context.MODE_PRIVATE), CalibrationDeps.io, CoroutineScope(SupervisorJob()),
        )
        store = s
        owner = app
        return s
    }
}
