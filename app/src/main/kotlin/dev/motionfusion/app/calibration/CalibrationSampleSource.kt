package dev.motionfusion.app.calibration

import android.hardware.Sensor
import android.hardware.SensorEvent
import android.hardware.SensorEventListener
import android.hardware.SensorManager
import android.os.Handler
import android.os.HandlerThread
import dev.motionfusion.core.calib.Calibrator
import dev.motionfusion.core.session.SessionStream
import kotlinx.coroutines.channels.Channel
import kotlinx.coroutines.channels.awaitClose
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.buffer
import kotlinx.coroutines.flow.callbackFlow

/** One raw reading for the calibration: device frame, the stream's SI unit (µT, rad/s, m/s²), `SensorEvent.timestamp`. */
data class CalibrationSample(val stream: SessionStream, val timestampNs: Long, val x: Double, val y: Double, val z: Double)

/**
 * Where the guided calibration gets its readings. [streams] are the streams [samples] delivers;
 * the screen fits the magnetometer and gyroscope on their uncalibrated streams when present (as
 * `fusion calibrate` does, [Calibrator]), so Android's own correction is not baked in.
 * Tests pass a fake; the app uses [SensorManagerSampleSource] (chosen in [CalibrationDeps]).
 */
interface CalibrationSampleSource {
    val streams: Set<SessionStream>

    /** Readings in arrival order, from collection start until it is cancelled. */
    fun samples(): Flow<CalibrationSample>
}

/**
 * The device's accelerometer, the uncalibrated gyroscope and magnetometer (else the calibrated
 * ones), registered with SensorManager at [samplingPeriodUs] on a HandlerThread of their own
 * while collected.
 */
class SensorManagerSampleSource(private val sensorManager: SensorManager, private val samplingPeriodUs: Int = 10_000) : CalibrationSampleSource {
    private val sensors: Map<SessionStream, Sensor> = run {
        fun pick(vararg s: SessionStream) = s.firstNotNullOfOrNull { st -> sensorManager.getDefaultSensor(st.androidType)?.let { st to it } }
        listOfNotNull(
            pick(SessionStream.ACCELEROMETER),
            pick(SessionStream.GYROSCOPE_UNCALIBRATED, SessionStream.GYROSCOPE),
            pick(SessionStream.MAGNETOMETER_UNCALIBRATED, SessionStream.MAGNETOMETER),
        ).toMap()
    }

    override val streams: Set<SessionStream> get() = sensors.keys

    /** The sensors used, for the per-device key of [CalibrationStore]. */
    fun sensorDescriptions(): List<String> = sensors.map { (stream, s) -> "${stream.key}: ${s.name} (${s.vendor})" }

    override fun samples(): Flow<CalibrationSample> = callbackFlow {
        val thread = HandlerThread("calibration-sensors").apply { start() }
        val byType = sensors.entries.associate { (stream, s) -> s.type to stream }
        val listener = object : SensorEventListener {
            override fun onSensorChanged(event: SensorEvent) {
                val stream = byType[event.sensor.type] ?: return
                val v = event.values
                trySend(CalibrationSample(stream, event.timestamp, v[0].toDouble(), v[1].toDouble(), v[2].toDouble()))
            }

            override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) = Unit
        }
        val handler = Handler(thread.looper)
        for (s in sensors.values) sensorManager.registerListener(listener, s, samplingPeriodUs, handler)
        awaitClose {
            sensorManager.unregisterListener(listener)
            thread.quitSafely()
        }
    }.buffer(Channel.UNLIMITED)
}
