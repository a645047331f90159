package dev.motionfusion.app.sensor

import android.hardware.Sensor
import android.hardware.SensorEvent
import android.hardware.SensorEventListener
import android.hardware.SensorEventListener2
import android.hardware.SensorManager
import android.os.Handler
import android.os.HandlerThread
import android.os.Process
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.WakeLockUse
import java.util.concurrent.atomic.AtomicInteger

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

    /**
     * The `maxReportLatencyUs` [start] registers the sensors of [streams] (null: all) with at
     * [rate]: chosen from their FIFO sizes ([ReportLatency]); 0 when they have none.
     */
    fun reportLatencyUs(rate: SamplingRate, streams: Set<SessionStream>? = null): Int

    /** The latency the listeners are registered with now (0: none, or stopped). */
    val registeredLatencyUs: Int

    /** The most events per second one registered sensor delivers (0 when stopped): what the reorder window must hold per second of batch. */
    val maxEventsPerSecond: Double

    /** Whether the sensors registered now need the CPU held to lose nothing with the screen off ([WakeLockNeed]). */
    val wakeLockNeed: WakeLockNeed get() = WakeLockNeed.NOT_WAKE_UP

    /** The wake-lock case [start] with [rate] and [streams] (null: all) comes to, for a recording's meta.json ([WakeLockNeed.use]). */
    fun wakeLockUse(rate: SamplingRate, streams: Set<SessionStream>? = null): WakeLockUse = WakeLockNeed.use(emptyMap(), 0)

    /**
     * [on]: a screen shows the events, so they are delivered as they come (report latency 0, in
     * force at once) and what the FIFOs hold is asked for ([flush]); off: batched again at
     * [registeredLatencyUs]. Stays as set across [start]s. Main thread.
     */
    fun immediate(on: Boolean)

    /** Asks every registered sensor to deliver what its FIFO holds now; [flushed] turns true once all did. */
    fun flush()

    /** True when every event batched at the last [flush] has been offered to the ring (and when nothing was batched). */
    val flushed: Boolean
}

/**
 * The app's one set of sensor listeners: every [SessionStream] sensor the device has (the
 * three filter inputs, their uncalibrated forms, the rotation vectors), each registered once at
 * the requested rate on one [HandlerThread]. Each event is copied into the [ring] at once, with
 * `SensorEvent.timestamp` and the accuracy read from the event itself: no allocation, no lock,
 * no I/O on the sensor thread. The live screen and the recorder both consume the ring.
 *
 * Hardware batching: the listener is registered with the report latency [reportLatencyUs] chooses
 * from the sensors' FIFO sizes, so that with nothing on screen the sensors deliver a batch every
 * few seconds instead of every event. While a screen shows the events ([immediate]), a second
 * listener that ignores its events is registered on the same sensors with latency 0: Android
 * batches at the smallest latency any listener asks for and hands every event to every listener,
 * so the events come at once, while the first listener (the one a recording reads) is never
 * re-registered: unregistering would switch the sensors off for a moment and lose events in the
 * middle of a recording.
 */
internal class SensorHub(private val sensorManager: SensorManager, private val ring: EventRing) : SensorSource {
    /** The default sensor of each stream the device has: its non-wake-up one, else whichever the device names its default. */
    override val sensors: Map<SessionStream, Sensor> = SensorStreams.all
        .mapNotNull { s -> (sensorManager.getDefaultSensor(s.androidType, false) ?: sensorManager.getDefaultSensor(s.androidType))?.let { s to it } }
        .toMap()

    /**
     * The sensor registered for each stream: its wake-up variant where the device has one that batches (a FIFO),
     * which wakes the phone itself to deliver ([WakeLockNeed]); else the default one. Same type and values; the
     * names shown and the calibration's device key stay those of [sensors].
     */
    private val registering: Map<SessionStream, Sensor> = sensors.mapValues { (stream, default) ->
        sensorManager.getDefaultSensor(stream.androidType, true)?.takeIf { it.isWakeUpSensor && it.fifoMaxEventCount > 0 } ?: default
    }

    /** The live screen's kinds the device has. */
    override val availableKinds: Set<SensorKind> = sensors.keys.mapNotNullTo(LinkedHashSet()) { SensorStreams.kindOf(it) }

    /** Name, vendor and limits of each live-screen sensor the device has. */
    override val info: Map<SensorKind, SensorInfo> = sensors.entries.mapNotNull { (stream, s) ->
        SensorStreams.kindOf(stream)?.let { it to SensorInfo(it, s.name ?: "?", s.vendor.orEmpty(), s.minDelay, s.maximumRange, s.resolution) }
    }.toMap()

    private var thread: HandlerThread? = null
    private var registered: List<Sensor> = emptyList()
    private var handler: Handler? = null
    private var immediate = false
    private var immediateRegistered = false

    /** The rate the listeners are registered at, or null when stopped. */
    @Volatile override var registeredRate: SamplingRate? = null
        private set

    @Volatile override var registeredLatencyUs: Int = 0
        private set

    @Volatile override var maxEventsPerSecond: Double = 0.0
        private set

    private val flushesPending = AtomicInteger()
    override val flushed: Boolean get() = flushesPending.get() <= 0

    private val listener = object : SensorEventListener2 {
        override fun onSensorChanged(event: SensorEvent) {
            val stream = SensorStreams.ofAndroidType(event.sensor.type) ?: return
            val v = event.values
            ring.offer(stream, event.timestamp, event.accuracy, v, v.size)
        }

        override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) = Unit // read on every event instead

        /** After the sensor's flushed events, on the same thread: they are in the ring. */
        override fun onFlushCompleted(sensor: Sensor) {
            flushesPending.updateAndGet { if (it > 0) it - 1 else 0 }
        }
    }

    /** Registered with latency 0 while a screen shows the events; its own events are ignored (the [listener] gets the same ones). */
    private val immediateListener = object : SensorEventListener {
        override fun onSensorChanged(event: SensorEvent) = Unit
        override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) = Unit
    }

    private fun wantedByStream(streams: Set<SessionStream>?): Map<SessionStream, Sensor> =
        if (streams == null) registering else registering.filterKeys { it in streams }

    private fun wanted(streams: Set<SessionStream>?): List<Sensor> = wantedByStream(streams).values.toList()

    override fun wakeLockUse(rate: SamplingRate, streams: Set<SessionStream>?): WakeLockUse =
        WakeLockNeed.use(wantedByStream(streams).mapValues { (_, s) -> s.isWakeUpSensor to s.fifoMaxEventCount }, reportLatencyUs(rate, streams))

    @Volatile override var wakeLockNeed: WakeLockNeed = WakeLockNeed.NOT_WAKE_UP
        private set

    override fun reportLatencyUs(rate: SamplingRate, streams: Set<SessionStream>?): Int =
        ReportLatency.choose(wanted(streams).map { SensorFifo(it.fifoReservedEventCount, it.fifoMaxEventCount, ReportLatency.eventsPerSecond(rate, it.minDelay)) })

    /** Registers the sensors of [streams] (null: all) at [rate] (re-registers when either differs). Main thread. */
    override fun start(rate: SamplingRate, streams: Set<SessionStream>?) {
        val wanted = wanted(streams)
        if (registeredRate == rate && registered == wanted) return
        val t = thread ?: HandlerThread("sensors", Process.THREAD_PRIORITY_URGENT_DISPLAY).apply { start() }.also { thread = it }
        if (registeredRate != null) unregisterAll()
        val handler = Handler(t.looper).also { this.handler = it }
        val latency = reportLatencyUs(rate, streams)
        for (sensor in wanted) sensorManager.registerListener(listener, sensor, rate.registerArgument, latency, handler)
        registeredRate = rate
        registered = wanted
        registeredLatencyUs = latency
        maxEventsPerSecond = wanted.maxOfOrNull { ReportLatency.eventsPerSecond(rate, it.minDelay) } ?: 0.0
        wakeLockNeed = WakeLockNeed.of(wanted.map { it.isWakeUpSensor to it.fifoMaxEventCount }, latency)
        if (immediate) registerImmediate()
    }

    override fun immediate(on: Boolean) {
        if (on == immediate) return
        immediate = on
        if (registeredRate == null) return
        if (on) {
            registerImmediate()
            flush()
        } else if (immediateRegistered) {
            sensorManager.unregisterListener(immediateListener)
            immediateRegistered = false
        }
    }

    private fun registerImmediate() {
        val rate = registeredRate ?: return
        if (registeredLatencyUs == 0 || immediateRegistered) return
        for (sensor in registered) sensorManager.registerListener(immediateListener, sensor, rate.registerArgument, 0, handler)
        immediateRegistered = true
    }

    override fun flush() {
        if (registeredLatencyUs == 0 || registered.isEmpty()) return
        flushesPending.addAndGet(registered.size)
        // False: nothing to flush (no listener registered); no completions will come.
        if (!sensorManager.flush(listener)) flushesPending.addAndGet(-registered.size)
    }

    private fun unregisterAll() {
        sensorManager.unregisterListener(listener)
        if (immediateRegistered) sensorManager.unregisterListener(immediateListener)
        immediateRegistered = false
        flushesPending.set(0)
    }

    /**
     * Unregisters, lets the thread handle the events already posted to it, and waits for it:
     * after this returns nothing more is offered to the ring.
     */
    override fun stop() {
        unregisterAll()
        registeredRate = null
        registeredLatencyUs = 0
        maxEventsPerSecond = 0.0
        registered = emptyList()
        handler = null
        val t = thread ?: return
        thread = null
        t.quitSafely()
        if (Thread.currentThread() !== t) t.join(2_000)
    }
}
