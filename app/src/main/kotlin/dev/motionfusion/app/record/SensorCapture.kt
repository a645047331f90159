package dev.motionfusion.app.record

import dev.motionfusion.core.session.SessionStream
import android.hardware.Sensor
import android.hardware.SensorEvent
import android.hardware.SensorEventListener
import android.hardware.SensorManager
import android.os.Handler
import android.os.HandlerThread
import android.os.Process

/**
 * The recording's own sensor listeners: every [SessionStream] the device has, registered on a
 * dedicated [HandlerThread] at [samplingPeriodUs] (0 = as fast as the device gives, which
 * `HIGH_SAMPLING_RATE_SENSORS` allows above 200 Hz). Each event is copied into the [ring] at
 * once — no allocation, no lock, no I/O on this thread — with `SensorEvent.timestamp` and the
 * accuracy read from the event itself.
 */
internal class SensorCapture(
    private val sensorManager: SensorManager,
    private val ring: EventRing,
    private val samplingPeriodUs: Int = SensorManager.SENSOR_DELAY_FASTEST,
) {
    /** The default sensor of each stream the device has. */
    val sensors: Map<SessionStream, Sensor> = SensorStreams.all
        .mapNotNull { s -> sensorManager.getDefaultSensor(s.androidType)?.let { s to it } }
        .toMap()

    private var thread: HandlerThread? = null

    private val listener = object : SensorEventListener {
        override fun onSensorChanged(event: SensorEvent) {
            val stream = SensorStreams.ofAndroidType(event.sensor.type) ?: return
            val v = event.values
            ring.offer(stream, event.timestamp, event.accuracy, v, v.size)
        }

        override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) = Unit // read on every event instead
    }

    /** The requested sampling period, µs, for the metadata. */
    val requestedPeriodUs: Int get() = samplingPeriodUs

    fun start() {
        check(thread == null) { "already started" }
        val t = HandlerThread("record-sensors", Process.THREAD_PRIORITY_URGENT_DISPLAY).apply { start() }
        thread = t
        val handler = Handler(t.looper)
        for ((_, sensor) in sensors) sensorManager.registerListener(listener, sensor, samplingPeriodUs, handler)
    }

    /**
     * Unregisters, lets the thread handle the events already posted to it, and waits for it:
     * after this returns nothing more is offered to the ring.
     */
    fun stop() {
        sensorManager.unregisterListener(listener)
        val t = thread ?: return
        thread = null
        t.quitSafely()
        if (Thread.currentThread() !== t) t.join(2_000)
    }
}
