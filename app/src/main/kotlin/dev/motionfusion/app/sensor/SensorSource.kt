package dev.motionfusion.app.sensor

import android.hardware.Sensor
import android.hardware.SensorEvent
import android.hardware.SensorEventListener
import android.hardware.SensorManager
import android.os.Handler
import android.os.HandlerThread
import android.os.Process
import kotlinx.coroutines.channels.Channel
import kotlinx.coroutines.channels.awaitClose
import kotlinx.coroutines.flow.Flow
import kotlinx.coroutines.flow.buffer
import kotlinx.coroutines.flow.callbackFlow

/** What the device says about one of its sensors (name and vendor are the driver's strings). */
data class SensorInfo(
    val kind: SensorKind,
    val name: String,
    val vendor: String,
    val minDelayUs: Int,
    val maxRange: Float,
    val resolution: Float,
)

/**
 * The device's sensors as a stream of [SensorSample]s.
 *
 * Listeners run on a [Handler] thread, never the main thread; each event's values are copied
 * before the framework reuses its `SensorEvent`, and `event.accuracy` is read on every event.
 * The stream is never conflated: every event reaches the collector, in order per sensor.
 * Listeners are registered when collection starts and unregistered when it stops.
 */
class SensorSource(private val sensorManager: SensorManager) {

    /** The default sensor of [kind], or null when the device has none. */
    fun sensor(kind: SensorKind): Sensor? = sensorManager.getDefaultSensor(kind.androidType)

    /** Kinds the device has. */
    fun availableKinds(): Set<SensorKind> = SensorKind.entries.filterTo(LinkedHashSet()) { sensor(it) != null }

    /** Name, vendor and limits of the sensor of [kind], or null when the device has none. */
    fun info(kind: SensorKind): SensorInfo? = sensor(kind)?.let {
        SensorInfo(kind, it.name ?: "?", it.vendor ?: "?", it.minDelay, it.maximumRange, it.resolution)
    }

    /**
     * Samples of [kinds] requested every [samplingPeriodUs] µs (a hint: Android may deliver
     * faster or slower; `SensorManager.SENSOR_DELAY_*` values are accepted too), on a
     * HandlerThread of their own.
     */
    fun samples(kinds: Set<SensorKind>, samplingPeriodUs: Int): Flow<SensorSample> = samples(kinds, samplingPeriodUs, null)

    /**
     * Samples of [kinds] at [rate]. Listeners run on [handler]'s thread when given (it must not
     * be the main thread), otherwise on a HandlerThread started for this collection and quit
     * when it ends.
     */
    fun samples(kinds: Set<SensorKind>, rate: SamplingRate, handler: Handler? = null): Flow<SensorSample> =
        samples(kinds, rate.registerArgument, handler)

    private fun samples(kinds: Set<SensorKind>, registerArgument: Int, given: Handler?): Flow<SensorSample> = callbackFlow {
        val thread = if (given == null) {
            HandlerThread("sensor-capture", Process.THREAD_PRIORITY_URGENT_DISPLAY).apply { start() }
        } else {
            null
        }
        val listener = object : SensorEventListener {
            override fun onSensorChanged(event: SensorEvent) {
                val kind = SensorKind.of(event.sensor.type) ?: return
                val v = event.values
                val w = if (kind.isRotationVector && v.size >= 4) v[3] else Float.NaN
                val headingAccuracy = if (kind == SensorKind.ROTATION_VECTOR && v.size >= 5) v[4] else Float.NaN
                trySend(SensorSample(kind, event.timestamp, v[0], v[1], v[2], event.accuracy, w, headingAccuracy))
            }

            override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) = Unit // read per event instead
        }
        val handler = given ?: Handler(thread!!.looper)
        for (kind in kinds) {
            sensor(kind)?.let { sensorManager.registerListener(listener, it, registerArgument, handler) }
        }
        awaitClose {
            sensorManager.unregisterListener(listener)
            thread?.quitSafely()
        }
    }.buffer(Channel.UNLIMITED)
}
