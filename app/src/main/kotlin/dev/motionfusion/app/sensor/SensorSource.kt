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

/**
 * The device's accelerometer, gyroscope and magnetometer as a stream of [SensorSample]s.
 *
 * Listeners run on a dedicated [HandlerThread], never the main thread; each event's values
 * are copied before the framework reuses its `SensorEvent`. The stream is never conflated:
 * every event reaches the collector, in order per sensor. Listeners are registered when
 * collection starts and unregistered (and the thread quit) when it stops.
 */
class SensorSource(private val sensorManager: SensorManager) {

    /** The default sensor of [kind], or null when the device has none. */
    fun sensor(kind: SensorKind): Sensor? = sensorManager.getDefaultSensor(kind.androidType)

    /** Kinds the device has. */
    fun availableKinds(): Set<SensorKind> = SensorKind.entries.filterTo(LinkedHashSet()) { sensor(it) != null }

    /**
     * Samples of [kinds] requested every [samplingPeriodUs] µs (a hint: Android may deliver
     * faster or slower; `SensorManager.SENSOR_DELAY_*` values are accepted too).
     */
    fun samples(kinds: Set<SensorKind>, samplingPeriodUs: Int): Flow<SensorSample> = callbackFlow {
        val thread = HandlerThread("sensor-capture", Process.THREAD_PRIORITY_URGENT_DISPLAY).apply { start() }
        val listener = object : SensorEventListener {
            override fun onSensorChanged(event: SensorEvent) {
                val kind = SensorKind.of(event.sensor.type) ?: return
                val v = event.values
                trySend(SensorSample(kind, event.timestamp, v[0], v[1], v[2], event.accuracy))
            }

            override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) = Unit // read per event instead
        }
        val handler = Handler(thread.looper)
        for (kind in kinds) {
            sensor(kind)?.let { sensorManager.registerListener(listener, it, samplingPeriodUs, handler) }
        }
        awaitClose {
            sensorManager.unregisterListener(listener)
            thread.quitSafely()
        }
    }.buffer(Channel.UNLIMITED)
}
