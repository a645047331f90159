package dev.motionfusion.app.sensor

import android.hardware.Sensor
import android.hardware.SensorEvent
import android.hardware.SensorEventListener
import android.hardware.SensorManager
import android.os.Handler
import android.os.HandlerThread
import android.os.Process
import dev.motionfusion.core.event.SessionStream

/** What the device says about one of its sensors (name and vendor are the driver's strings; the vendor empty when it gives none). */
data class SensorInfo(
    val kind: SensorKind,
    val name: String,
    val vendor: String,
    val minDelayUs: Int,
    val maxRange: Float,
    val resolution: Float,
)

/** Where the capture's events come from: the device's sensors ([SensorHub]) or a test's fake. */
internal interface SensorSource {
    /** The default sensor of each stream the device has (empty for a fake). */
    val sensors: Map<SessionStream, Sensor>

    /** The streams delivered. */
    val streams: Set<SessionStream> get() = sensors.keys

    /** The live screen's kinds the device has. */
    val availableKinds: Set<SensorKind>

    /** Name, vendor and limits of each live-screen sensor the device has. */
    val info: Map<SensorKind, SensorInfo>

    /** The rate the sensors are registered at, or null when stopped. */
    val registeredRate: SamplingRate?

    /**
     * Registers the sensors of [streams] (null: every stream) at [rate] into the ring;
     * re-registers when the rate or the streams differ from those registered.
     */
    fun start(rate: SamplingRate, streams: Set<SessionStream>? = null)

    /** Unregisters; after it returns nothing more is offered to the ring. */
    fun stop()
}

/**
 * The app's one set of sensor listeners: every [SessionStream] sensor the device has (the
 * three filter inputs, their uncalibrated forms, the rotation vectors), each registered once at
 * the requested rate on one [HandlerThread]. Each event is copied into the [ring] at once, with
 * `SensorEvent.timestamp` and the accuracy read from the event itself: no allocation, no lock,
 * no I/O on the sensor thread. The live screen and the recorder both consume the ring.
 */
internal class SensorHub(private val sensorManager: SensorManager, private val ring: EventRing) : SensorSource {
    /** The default sensor of each stream the device has. */
    override val sensors: Map<SessionStream, Sensor> = SensorStreams.all
        .mapNotNull { s -> sensorManager.getDefaultSensor(s.androidType)?.let { s to it } }
        .toMap()

    /** The live screen's kinds the device has. */
    override val availableKinds: Set<SensorKind> = sensors.keys.mapNotNullTo(LinkedHashSet()) { SensorStreams.kindOf(it) }

    /** Name, vendor and limits of each live-screen sensor the device has. */
    override val info: Map<SensorKind, SensorInfo> = sensors.entries.mapNotNull { (stream, s) ->
        SensorStreams.kindOf(stream)?.let { it to SensorInfo(it, s.name ?: "?", s.vendor.orEmpty(), s.minDelay, s.maximumRange, s.resolution) }
    }.toMap()

    private var thread: HandlerThread? = null
    private var registered: List<Sensor> = emptyList()

    /** The rate the listeners are registered at, or null when stopped. */
    @Volatile override var registeredRate: SamplingRate? = null
        private set

    private val listener = object : SensorEventListener {
        override fun onSensorChanged(event: SensorEvent) {
            val stream = SensorStreams.ofAndroidType(event.sensor.type) ?: return
            val v = event.values
            ring.offer(stream, event.timestamp, event.accuracy, v, v.size)
        }

        override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) = Unit // read on every event instead
    }

    /** Registers the sensors of [streams] (null: all) at [rate] (re-registers when either differs). Main thread. */
    override fun start(rate: SamplingRate, streams: Set<SessionStream>?) {
        val wanted = (if (streams == null) sensors else sensors.filterKeys { it in streams }).values.toList()
        if (registeredRate == rate && registered == wanted) return
        val t = thread ?: HandlerThread("sensors", Process.THREAD_PRIORITY_URGENT_DISPLAY).apply { start() }.also { thread = it }
        if (registeredRate != null) sensorManager.unregisterListener(listener)
        val handler = Handler(t.looper)
        for (sensor in wanted) sensorManager.registerListener(listener, sensor, rate.registerArgument, handler)
        registeredRate = rate
        registered = wanted
    }

    /**
     * Unregisters, lets the thread handle the events already posted to it, and waits for it:
     * after this returns nothing more is offered to the ring.
     */
    override fun stop() {
        sensorManager.unregisterListener(listener)
        registeredRate = null
        registered = emptyList()
        val t = thread ?: return
        thread = null
        t.quitSafely()
        if (Thread.currentThread() !== t) t.join(2_000)
    }
}
