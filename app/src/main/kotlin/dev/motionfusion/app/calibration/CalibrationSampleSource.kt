package dev.motionfusion.app.calibration

import dev.motionfusion.app.fusion.Capture
import dev.motionfusion.app.fusion.RawListener
import dev.motionfusion.core.calib.Calibrator
import dev.motionfusion.core.event.SessionStream
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.channels.Channel
import kotlinx.coroutines.channels.awaitClose
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.buffer
import kotlinx.coroutines.flow.callbackFlow
import kotlinx.coroutines.flow.flowOn

/** One raw reading for the calibration: device frame, the stream's SI unit (µT, rad/s, m/s²), `SensorEvent.timestamp`. */
data class CalibrationSample(val stream: SessionStream, val timestampNs: Long, val x: Double, val y: Double, val z: Double)

/**
 * Where the guided calibration gets its readings. [streams] are the streams [samples] delivers;
 * the screen fits the magnetometer and gyroscope on their uncalibrated streams when present (as
 * `fusion calibrate` does, [Calibrator]), so Android's own correction is not baked in.
 * The app uses [CaptureSampleSource]; tests pass a fake.
 */
interface CalibrationSampleSource {
    val streams: Set<SessionStream>

    /** Readings in arrival order, from collection start until it is cancelled. */
    fun samples(): Flow<CalibrationSample>
}

/** The streams the calibration reads of [available]: the accelerometer, the uncalibrated gyroscope and magnetometer (else the calibrated ones). */
internal fun calibrationStreams(available: Set<SessionStream>): Set<SessionStream> = listOfNotNull(
    SessionStream.ACCELEROMETER.takeIf { it in available },
    Calibrator.gyroscopeStream(available),
    Calibrator.magnetometerStream(available),
).toCollection(LinkedHashSet())

/**
 * The calibration's readings from the app's one capture ([Capture]: the sensors registered
 * once, at the user's rate): while collected it holds the capture (as the live screen does)
 * and listens to its ordered raw events. Nothing is registered twice when a recording or the
 * live screen runs at the same time.
 */
internal class CaptureSampleSource(private val capture: Capture) : CalibrationSampleSource {
    override val streams: Set<SessionStream> = calibrationStreams(capture.streams)

    override fun samples(): Flow<CalibrationSample> = callbackFlow {
        val listener = RawListener { stream, t, _, v, o ->
            if (stream in streams) trySend(CalibrationSample(stream, t, v[o].toDouble(), v[o + 1].toDouble(), v[o + 2].toDouble()))
        }
        capture.listen(listener)
        capture.acquire(onScreen = true)
        awaitClose {
            capture.unlisten(listener)
            capture.release(onScreen = true)
        }
    }.buffer(Channel.UNLIMITED).flowOn(Dispatchers.Main.immediate)
}
