package dev.motionfusion.app.calibration

import android.hardware.Sensor
import dev.motionfusion.app.record.Recordings
import dev.motionfusion.app.platform.Clock
import dev.motionfusion.core.calib.CalibrationSettings
import dev.motionfusion.core.event.SessionStream
import kotlinx.coroutines.CoroutineDispatcher

/** What the calibration screen needs, from the application's object graph. */
internal interface CalibrationDependencies {
    /** This device's stored calibration. */
    val calibrationStore: CalibrationStore

    /** Where its readings come from: the app's one capture ([CaptureSampleSource]). */
    val calibrationSource: CalibrationSampleSource

    /** Where the fits run (Dispatchers.Default in the app). */
    val calibrationCompute: CoroutineDispatcher

    /** Where the store reads and writes. */
    val io: CoroutineDispatcher

    /** The recording state (the still recording runs as any recording). */
    val recordings: Recordings

    val clock: Clock

    /** Implemented by the application. */
    interface Provider {
        val calibrationDependencies: CalibrationDependencies
    }

    companion object {
        /** The fits' settings on the phone: the defaults of `fusion calibrate`, fewer kept magnetometer readings (a few minutes at 100 Hz). */
        val settings = CalibrationSettings(maxMagSamples = 20_000)

        /** The device key of [sensors] (the streams the calibration reads: [calibrationStreams]). */
        fun deviceKey(sensors: Map<SessionStream, Sensor>): DeviceKey =
            DeviceKey.thisDevice(calibrationStreams(sensors.keys).map { stream -> sensors.getValue(stream).let { "${stream.key}: ${it.name} (${it.vendor})" } })
    }
}
