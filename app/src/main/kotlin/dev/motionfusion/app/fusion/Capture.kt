package dev.motionfusion.app.fusion

import dev.motionfusion.app.sensor.WakeLockNeed
import dev.motionfusion.core.session.WakeLockUse
import dev.motionfusion.app.sensor.EventRing
import dev.motionfusion.app.sensor.GyroSaturation
import dev.motionfusion.app.sensor.ReorderWindow
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.sensor.SensorHub
import dev.motionfusion.app.sensor.SensorSource
import dev.motionfusion.app.sensor.SensorInfo
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.CalibrationRoute
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.event.SessionStream
import java.util.concurrent.locks.LockSupport
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.launch
import dev.motionfusion.app.settings.LiveSettings

/**
 * A consumer of the capture's ordered events besides the live screen: the recorder. Called on
 * the capture thread only, in timestamp order. Any method but [end] may throw; the tap is then
 * ended with [TapEnd.Failed].
 */
internal interface CaptureTap {
    /** One sensor event, values at [values]`[offset..]` ([SessionStream.valueCount] of them). */
    fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int)

    /** After the gyroscope event at [timestampNs] stepped the one live [filter] (initialised). */
    fun stepped(timestampNs: Long, filter: MadgwickFilter)

    /** After each batch, with the monotonic clock: flush, checkpoint, check space. False: it has ended itself. */
    fun afterBatch(nowNs: Long): Boolean

    /** Detached: called once, last. */
    fun end(end: TapEnd)
}

/**
 * A reader of the raw events besides the recorder (the calibration screen). Called on the
 * capture thread, in timestamp order, with the values at [values]`[offset..]`; it must not
 * block and must not keep [values].
 */
internal fun interface RawListener {
    fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int)
}

/**
 * A reader of the live filter's orientation (the stream): called on the capture thread after each
 * filter step, with the quaternion sensor → ENU [w, x, y, z]; it must not block.
 */
internal fun interface OrientationListener {
    fun oriented(timestampNs: Long, qw: Double, qx: Double, qy: Double, qz: Double)
}

/** Why a tap was detached. */
internal sealed interface TapEnd {
    /** [Capture.detach]: every event up to the request was handed over. */
    data object Detached : TapEnd

    /** The ring was full and refused events just before the one at [atTimestampNs]. */
    data class EventsLost(val atTimestampNs: Long) : TapEnd

    /** A tap method threw. */
    data class Failed(val error: Exception) : TapEnd
}

/**
 * The app's one capture path: every sensor registered once ([SensorHub], one sensor thread, at
 * the user's rate) into one lock-free [EventRing]; one capture thread drains it through a
 * [ReorderWindow] into timestamp order and feeds ONE [FusionPipeline], whose filter has the
 * user's settings, and an attached recorder ([CaptureTap]), which writes the raw events and
 * that same filter's output. With a calibration applied, the filter reads the corrected
 * streams ([CalibrationRoute]: the uncalibrated magnetometer and gyroscope corrected in place
 * of the calibrated ones); the recorder still gets every raw event. The live state is published as [state] (at most every
 * [publishIntervalNs]; the snapshot is the only allocation, per batch, not per event).
 *
 * Owned by the application's object graph. It runs between the first [acquire] and the last
 * [release]: the visible live screen and the foreground recording service each hold it. Filter
 * and rate changes wait while a recording is attached, so that a session has one set of
 * settings, the one in its meta.json. [acquire], [release] and [attach]/[detach] are called on
 * the main thread.
 *
 * Hardware batching: while no holder shows the results on screen (only a recording holds it), the
 * sensors deliver in batches of up to their report latency ([SensorSource.reportLatencyUs], from
 * their FIFO sizes); the reorder window then widens to the latency and a margin ([windowFor]) and
 * its queues grow to hold it ([capacityFor]), so that the sensors' separate batches still come out
 * in the order a replay of the recording reads them. When a screen acquires it again, the events
 * come at once ([SensorSource.immediate]), the FIFOs are flushed, and the window narrows back once
 * they have arrived. A recording's start and end wait (at most [FLUSH_TIMEOUT_NS]) for the FIFOs'
 * events, so that every event up to the request belongs to the recording, and none after it.
 */
class Capture internal constructor(
    /** The one queue between the sensor thread and the capture thread. */
    internal val ring: EventRing,
    private val hub: SensorSource,
    private val settings: StateFlow<LiveSettings>,
    private val scope: CoroutineScope,
    /** The calibration the live filter applies while no recording is attached (null: none). */
    private val calibration: StateFlow<Calibration?> = MutableStateFlow(null),
    reorderWindowNs: Long = ReorderWindow.DEFAULT_WINDOW_NS,
    private val nanoTime: () -> Long = System::nanoTime,
    /** False in tests: nothing runs the capture thread; the test calls [pump]. */
    private val runThread: Boolean = true,
    private val publishIntervalNs: Long = 4_000_000L,
    /** With no event for this long (monotonic clock), the reorder window is emptied. */
    private val quietFlushNs: Long = 100_000_000L,
) {
    private val baseWindowNs = reorderWindowNs
    private val reorder = ReorderWindow(windowNs = reorderWindowNs)

    /** The report latency the reorder window is set up for, and the window it needs (capture thread). */
    private var batchLatencyUs = 0
    private var batchWindowNs = reorderWindowNs

    /** The live-screen kinds the device has. */
    val available: Set<SensorKind> = hub.availableKinds

    /** Name, vendor and limits of each sensor the device has. */
    val sensorInfo: Map<SensorKind, SensorInfo> = hub.info

    /** The streams the device has, with their sensors (for a session's meta.json). */
    internal val sensors get() = hub.sensors

    /** The streams the device delivers. */
    internal val streams: Set<SessionStream> get() = hub.streams

    /** The filter's gyroscope saturation from this device's gyroscope range (written into meta.json with the other filter settings). */
    private val gyroSaturation = GyroSaturation.fromRange(sensorInfo[SensorKind.GYROSCOPE]?.maxRange)

    private val pipeline = FusionPipeline(available, settings.value, gyroSaturation)
    private val stateFlow = MutableStateFlow(pipeline.snapshot())

    /** The latest published fusion result. */
    val state: StateFlow<FusionState> = stateFlow.asStateFlow()

    private var users = 0
    private var thread: Thread? = null
    @Volatile private var running = false

    // Requests from the main thread, taken by the capture thread at its next batch.
    @Volatile private var attachRequest: Attach? = null
    @Volatile private var detachRequest: CaptureTap? = null
    private var tap: CaptureTap? = null
    @Volatile private var recording = false
    @Volatile private var listeners: Array<RawListener> = emptyArray()
    @Volatile private var orientationListeners: Array<OrientationListener> = emptyArray()
    private val q = DoubleArray(4)

    /** The calibration applied now, its routing, and one corrected reading; the store's value last looked at. */
    private var applied: Calibration? = null
    private var offered: Any? = NOT_OFFERED
    private var route: CalibrationRoute? = null
    private val corrected = DoubleArray(3)

    private var lastEventNs = 0L
    private var lastPublishNs = Long.MIN_VALUE / 2
    private var changed = false

    private val dispatch = EventRing.Consumer { stream, t, accuracy, values, offset, afterGap -> dispatch(stream, t, accuracy, values, offset, afterGap) }
    private val toReorder = EventRing.Consumer { stream, t, accuracy, values, offset, afterGap ->
        reorder.add(stream, t, accuracy, values, offset, afterGap, dispatch)
    }

    init {
        scope.launch { settings.collect { onSettings(it) } }
    }

    /** True while listeners are registered. */
    val isRunning: Boolean get() = users > 0

    /** Events the ring refused because the capture thread fell behind. */
    val refusedEvents: Long get() = ring.refused

    /** Events that arrived later than the reorder window allowed (passed on out of order). */
    val lateEvents: Long get() = synchronized(pipeline) { reorder.late }

    /** The filter settings a recording started now would run with (and write into meta.json). */
    fun filterSettingsFor(s: LiveSettings): FilterSettings = FusionPipeline(available, s, gyroSaturation).filterSettings

    /**
     * [c] if the live filter can apply it (the device has every stream it corrects), else null:
     * what a recording started now applies (and writes into meta.json as applied).
     */
    fun calibrationFor(c: Calibration?): Calibration? = c?.takeIf { streams.containsAll(it.streams()) }

    /** The calibration the live filter applies now, or null. */
    internal fun calibrationInUse(): Calibration? = synchronized(pipeline) { applied }

    /** Adds [l]: it gets every raw event from the next batch on. Any thread. */
    @Synchronized
    internal fun listen(l: RawListener) {
        listeners += l
    }

    /** Removes [l]; after the current batch it gets no more events. Any thread. */
    @Synchronized
    internal fun unlisten(l: RawListener) {
        listeners = listeners.filter { it !== l }.toTypedArray()
    }

    /** Adds [l]: it gets the orientation after every filter step from the next batch on. Any thread. */
    @Synchronized
    internal fun listen(l: OrientationListener) {
        orientationListeners += l
    }

    /** Removes [l]; after the current batch it gets no more orientations. Any thread. */
    @Synchronized
    internal fun unlisten(l: OrientationListener) {
        orientationListeners = orientationListeners.filter { it !== l }.toTypedArray()
    }

    /** The settings of the filter in use. */
    internal fun filterSettingsInUse(): FilterSettings = synchronized(pipeline) { pipeline.filterSettings }

    /** Users showing the capture on screen (the live screen, calibration, the stream): the thread wakes more often while there are any. */
    @Volatile private var onScreen = 0

    /** When (monotonic) the last screen came after none: the wide reorder window narrows once the FIFOs flushed then have arrived. */
    @Volatile private var screenSinceNs = 0L

    /** When (monotonic) the pending attach or detach asked the sensors to flush their FIFOs. */
    @Volatile private var flushAskedNs = 0L

    /** The report latency the sensors are registered with now (0: every event as it comes). */
    val reportLatencyUs: Int get() = hub.registeredLatencyUs

    /** Whether the sensors registered now need the CPU held to lose nothing with the screen off. */
    internal val wakeLockNeed: WakeLockNeed get() = hub.wakeLockNeed

    /** Whether a recording of [streams] (null: all) at [rate] holds the wake lock, and why, for its meta.json. */
    internal fun wakeLockUseFor(rate: SamplingRate, streams: Set<SessionStream>? = null): WakeLockUse = hub.wakeLockUse(rate, streams)

    /** The report latency a recording of [streams] (null: all) at [rate] is registered with, for its meta.json. */
    internal fun reportLatencyUsFor(rate: SamplingRate, streams: Set<SessionStream>? = null): Int = hub.reportLatencyUs(rate, streams)

    /** The reorder window in force now (sensor time; capture thread, tests). */
    internal val reorderWindowNs: Long get() = synchronized(pipeline) { reorder.windowNs }

    /** Events each stream's reorder queue holds now (tests). */
    internal val reorderCapacity: Int get() = synchronized(pipeline) { reorder.capacity }

    /**
     * One more user (the visible live screen, a recording): the first one registers the sensors.
     * [onScreen]: the user shows the results as they come (a screen), rather than only recording them.
     */
    @JvmOverloads
    fun acquire(onScreen: Boolean = false) {
        if (onScreen) {
            if (this.onScreen == 0) {
                // Before the count: the capture thread must not see a screen without the flush it waits for.
                hub.immediate(true)
                screenSinceNs = nanoTime()
            }
            this.onScreen++
        }
        users++
        if (users > 1) return
        hub.start(settings.value.rate)
        if (runThread) {
            running = true
            thread = Thread(::loop, "capture").apply {
                priority = Thread.NORM_PRIORITY + 1
                start()
            }
        }
    }

    /** One user less ([onScreen] as it acquired): the last one unregisters the sensors and stops the capture thread. */
    @JvmOverloads
    fun release(onScreen: Boolean = false) {
        if (users == 0) return
        if (onScreen && this.onScreen > 0) {
            this.onScreen--
            if (this.onScreen == 0) hub.immediate(false)
        }
        users--
        if (users > 0) return
        hub.stop()
        running = false
        thread?.let {
            LockSupport.unpark(it)
            it.join(2_000)
        }
        thread = null
        synchronized(pipeline) {
            ring.drain(toReorder)
            reorder.flush(dispatch)
            publish()
        }
    }

    /**
     * Starts feeding [tap] from the next event, with a filter started afresh with [settings]'
     * filter settings (those of [filterSettingsFor], which the caller wrote into meta.json) on
     * readings corrected by [calibration] (that of [calibrationFor], also in meta.json), and
     * the sensors of [streams] (null: all) registered at [settings]' rate. Call while acquired.
     */
    internal fun attach(tap: CaptureTap, settings: LiveSettings, calibration: Calibration? = null, streams: Set<SessionStream>? = null) {
        check(isRunning) { "attach needs a running capture" }
        recording = true
        hub.start(settings.rate, streams)
        askFlush()
        attachRequest = Attach(tap, settings, calibrationFor(calibration))
        thread?.let(LockSupport::unpark)
    }

    private class Attach(val tap: CaptureTap, val settings: LiveSettings, val calibration: Calibration?)

    /** Batching: asks for the FIFOs' events, which the pending attach or detach waits for. */
    private fun askFlush() {
        if (hub.registeredLatencyUs == 0) return
        flushAskedNs = nanoTime()
        hub.flush()
    }

    /** Every event up to the last flush request is in the ring, or the sensors did not say so in time. */
    private fun flushArrived(now: Long): Boolean = hub.flushed || now - flushAskedNs >= FLUSH_TIMEOUT_NS

    /**
     * Sets the reorder window up for the registered report latency, before a batch is drained:
     * its queues sized for it (allocated here, not per event), and wide while batching with
     * nothing on screen. Narrowing waits for [narrowAfterDrain].
     */
    private fun configureReorder() {
        val latency = hub.registeredLatencyUs
        if (latency != batchLatencyUs) {
            batchLatencyUs = latency
            batchWindowNs = windowFor(latency, baseWindowNs)
            reorder.ensureCapacity(capacityFor(hub.maxEventsPerSecond, batchWindowNs))
        }
        if (latency == 0) reorder.windowNs = baseWindowNs
        else if (onScreen == 0) reorder.windowNs = batchWindowNs
    }

    /**
     * With a screen showing the events ([screen], read before [flushedBefore]), the wide window
     * narrows once the FIFOs flushed when the screen came have been drained ([flushedBefore]: read
     * before the drain, which [drainedAll]),
     * or after as long as a batch can take; narrowed earlier, one sensor's flushed batch would be
     * released before another's older events arrived.
     */
    private fun narrowAfterDrain(screen: Boolean, flushedBefore: Boolean, drainedAll: Boolean, now: Long) {
        if (!screen || reorder.windowNs <= baseWindowNs) return
        if ((flushedBefore && drainedAll) || now - screenSinceNs >= batchWindowNs) reorder.windowNs = baseWindowNs
    }

    /** With no event for this long the reorder window is emptied: longer than the time between two batches. */
    private fun quietNs(): Long = quietFlushNs + (reorder.windowNs - baseWindowNs).coerceAtLeast(0L)

    /** Hands [tap] every event up to now, then ends it ([CaptureTap.end] on the capture thread). */
    internal fun detach(tap: CaptureTap) {
        askFlush()
        detachRequest = tap
        thread?.let(LockSupport::unpark)
    }

    /** One batch of the capture thread: returns the events drained. Tests call it directly. */
    internal fun pump(): Int = synchronized(pipeline) {
        configureReorder()
        // The screen count first: a screen seen here had its flush asked before, so the flag read next is that flush's.
        val screen = onScreen > 0
        val flushedBefore = hub.flushed
        val requestReady = (attachRequest == null && detachRequest == null) || flushArrived(nanoTime())
        attachRequest?.takeIf { requestReady }?.let { a ->
            attachRequest = null
            // Events queued before the start belong to the time before it.
            ring.drain(toReorder)
            reorder.flush(dispatch)
            pipeline.reconfigure(a.settings)
            applyCalibration(a.calibration)
            offered = NOT_OFFERED // after the recording, the store's calibration is looked at again
            pipeline.restartFilter()
            tap = a.tap
        }
        val n = ring.drain(toReorder, BATCH)
        val now = nanoTime()
        narrowAfterDrain(screen, flushedBefore, n < BATCH, now)
        if (n > 0) {
            lastEventNs = now
            changed = true
        } else if (reorder.size > 0 && now - lastEventNs >= quietNs()) {
            reorder.flush(dispatch)
            changed = true
        }
        val t = tap
        if (t != null && detachRequest === t && requestReady) {
            detachRequest = null
            ring.drain(toReorder)
            reorder.flush(dispatch)
            endTap(TapEnd.Detached)
        }
        tap?.let { current ->
            val goOn = try {
                current.afterBatch(now)
            } catch (e: Exception) {
                endTap(TapEnd.Failed(e))
                true
            }
            if (!goOn) endTap(null)
        }
        if (!recording) {
            applySettings(settings.value)
            val c = calibration.value
            if (c !== offered) {
                offered = c
                applyCalibration(calibrationFor(c))
            }
        }
        if (changed && now - lastPublishNs >= publishIntervalNs) {
            lastPublishNs = now
            publish()
        }
        n
    }

    private fun loop() {
        while (running) {
            val n = pump()
            wakeUps++
            var wait = waitAfter(n, reorder.size, tap != null, onScreen > 0, quietNs())
            // An attach or detach waiting for the FIFOs' events: looked at again soon.
            if (attachRequest != null || detachRequest != null) wait = minOf(wait, ON_SCREEN_WAIT_NS)
            if (n == 0) ring.awaitEvent(wait) else if (wait > 0) LockSupport.parkNanos(wait)
        }
    }

    /** Times the capture thread ran a batch (for the battery benchmark). */
    @Volatile internal var wakeUps: Long = 0L
        private set

    private fun dispatch(stream: SessionStream, t: Long, accuracy: Int, values: FloatArray, offset: Int, afterGap: Boolean) {
        if (afterGap && tap != null) endTap(TapEnd.EventsLost(t))
        tap?.let {
            try {
                it.raw(stream, t, accuracy, values, offset)
            } catch (e: Exception) {
                endTap(TapEnd.Failed(e))
            }
        }
        val l = listeners
        for (i in l.indices) l[i].raw(stream, t, accuracy, values, offset)
        val r = route
        val target = if (r == null) stream else r.target(stream) ?: return
        val kind = SensorStreams.kindOf(target) ?: return
        val correction = r?.correction(stream)
        val stepped = if (correction == null) {
            pipeline.onEvent(kind, t, accuracy, values, offset, stream.valueCount)
        } else {
            corrected[0] = values[offset].toDouble()
            corrected[1] = values[offset + 1].toDouble()
            corrected[2] = values[offset + 2].toDouble()
            correction.applyInPlace(corrected)
            pipeline.onCorrected(kind, t, accuracy, corrected[0], corrected[1], corrected[2])
        }
        if (stepped) {
            tap?.let {
                try {
                    it.stepped(t, pipeline.filter)
                } catch (e: Exception) {
                    endTap(TapEnd.Failed(e))
                }
            }
            val o = orientationListeners
            if (o.isNotEmpty()) {
                pipeline.filter.orientationInto(q, 0)
                for (i in o.indices) o[i].oriented(t, q[0], q[1], q[2], q[3])
            }
        }
    }

    /** Detaches the tap; [end] null: it ended itself. */
    private fun endTap(end: TapEnd?) {
        val t = tap ?: return
        tap = null
        recording = attachRequest != null
        if (end != null) t.end(end)
        // A rate chosen during the recording, and every stream, are registered now.
        scope.launch { onSettings(settings.value) }
    }

    private fun onSettings(s: LiveSettings) {
        if (recording) return // applied when the recording ends
        // The new registration's events follow in order; any late ones are counted.
        if (isRunning) hub.start(s.rate)
        if (!runThread || thread == null) synchronized(pipeline) { applySettings(s); publish() } else thread?.let(LockSupport::unpark)
    }

    private fun applyCalibration(c: Calibration?) {
        if (c === applied) return
        applied = c
        route = c?.let(::CalibrationRoute)
        changed = true
    }

    private fun applySettings(s: LiveSettings) {
        if (s == pipeline.settings) return
        pipeline.reconfigure(s)
        changed = true
    }

    private fun publish() {
        changed = false
        stateFlow.value = pipeline.snapshot()
    }

    internal companion object {
        /** Slots in the ring (36 bytes each): 2^17 ≈ 4.7 MB, ~37 s of 7 streams at 500 Hz. */
        const val DEFAULT_RING_CAPACITY = 1 shl 17
        private const val BATCH = 4096

        /** While a screen shows the results: a batch at most every 10 ms (100 wake-ups a second, under a display frame). */
        const val ON_SCREEN_WAIT_NS = 10_000_000L

        /** Recording with nothing on screen: a batch every 100 ms (10 a second; the recorder flushes every 0.5 s). */
        const val OFF_SCREEN_WAIT_NS = 100_000_000L

        /** With nothing queued, no recording and nothing in the reorder window: a look at the settings at least every second. */
        const val IDLE_WAIT_NS = 1_000_000_000L

        /**
         * How long the capture thread waits after a batch of [drained] events: none when the ring
         * had more than a batch; after some events, the interval that lets the next ones gather
         * ([ON_SCREEN_WAIT_NS] or [OFF_SCREEN_WAIT_NS]: one wake-up per interval, not one per
         * event); after none, until an event comes (the producer wakes it), at most until the
         * reorder window is due to be emptied ([quietFlushNs]) or the recorder's next look.
         * Before, the thread woke every 2 ms whatever came.
         */
        fun waitAfter(drained: Int, reordering: Int, recording: Boolean, onScreen: Boolean, quietFlushNs: Long = 100_000_000L): Long = when {
            drained >= BATCH -> 0L
            drained > 0 -> if (onScreen) ON_SCREEN_WAIT_NS else OFF_SCREEN_WAIT_NS
            reordering > 0 -> quietFlushNs
            recording -> OFF_SCREEN_WAIT_NS * 5
            else -> IDLE_WAIT_NS
        }
        private val NOT_OFFERED = Any()

        /** The longest a recording's start or end waits for the sensors to deliver their FIFOs. */
        const val FLUSH_TIMEOUT_NS = 1_000_000_000L

        /**
         * The reorder window for a report latency of [latencyUs]: [baseNs] without batching; with it,
         * the latency and a quarter (rates are hints, a sensor's batch may come late) plus [baseNs]:
         * another sensor's batch holding older events arrives, at the latest, a latency after them.
         */
        fun windowFor(latencyUs: Int, baseNs: Long = ReorderWindow.DEFAULT_WINDOW_NS): Long =
            if (latencyUs <= 0) baseNs else baseNs + latencyUs * 1_250L

        /**
         * Events per stream the reorder window must hold for [windowNs] of a stream delivering
         * [eventsPerSecond]: twice that (a device may deliver faster than asked), at least
         * [ReorderWindow.DEFAULT_CAPACITY].
         */
        fun capacityFor(eventsPerSecond: Double, windowNs: Long): Int =
            maxOf(ReorderWindow.DEFAULT_CAPACITY, kotlin.math.ceil(2.0 * eventsPerSecond * windowNs / 1e9).toInt())
    }
}
