package dev.motionfusion.app.live

import android.hardware.Sensor
import dev.motionfusion.app.record.Recorder
import dev.motionfusion.app.sensor.EventRing
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.sensor.SensorInfo
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSource
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.event.SessionStream
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.flow.MutableStateFlow
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.fusion.Capture

/**
 * Sensors that are only a set of kinds: the test offers their events into the ring itself (it is the
 * sensor thread). [latencyUs]: the report latency they register with, as a device with a FIFO
 * would choose ([dev.motionfusion.app.sensor.ReportLatency]); while it is > 0, [flush] requests
 * stay pending until the test calls [flushCompleted] (the sensor thread has offered the FIFOs' events).
 */
internal class FakeSensorSource(
    override val availableKinds: Set<SensorKind> = SensorKind.entries.toSet(),
    var latencyUs: Int = 0,
    override var maxEventsPerSecond: Double = 200.0,
) : SensorSource {
    override val sensors: Map<SessionStream, Sensor> = emptyMap()
    override val streams: Set<SessionStream> = SensorStreams.all.toSet()
    override val info: Map<SensorKind, SensorInfo> = emptyMap()
    override var registeredRate: SamplingRate? = null
    override var registeredLatencyUs: Int = 0

    /** As [immediate] last set it: a screen asked for every event at once. */
    var immediate = false
        private set

    /** Flushes asked for so far. */
    var flushRequests = 0
        private set

    override var flushed: Boolean = true
        private set

    override fun reportLatencyUs(rate: SamplingRate, streams: Set<SessionStream>?): Int = latencyUs

    override fun start(rate: SamplingRate, streams: Set<SessionStream>?) {
        registeredLatencyUs = latencyUs
        if (registeredRate == rate) return
        registeredRate = rate
    }

    override fun stop() {
        registeredRate = null
        registeredLatencyUs = 0
    }

    override fun immediate(on: Boolean) {
        if (on == immediate) return
        immediate = on
        if (on) flush()
    }

    override fun flush() {
        if (registeredLatencyUs == 0) return
        flushRequests++
        flushed = false
    }

    /** The sensors delivered what their FIFOs held when [flush] was asked. */
    fun flushCompleted() {
        flushed = true
    }
}

/**
 * A [Capture] on the JVM without threads: the test is the sensor thread ([offer]) and the
 * capture thread ([pump]); time is [nowNs], set by the test.
 */
internal class TestCapture(
    settings: LiveSettings = LiveSettings(),
    kinds: Set<SensorKind> = SensorKind.entries.toSet(),
    ringCapacity: Int = 1 shl 16,
    reorderWindowNs: Long = 30_000_000L,
    /** 0: the state is published after every batch (the app: at most every 4 ms). */
    publishIntervalNs: Long = 0L,
    /** The calibration the live filter applies (the store's active one in the app). */
    calibration: Calibration? = null,
    /** The sensors' report latency while nothing is on screen (0: no hardware batching). */
    latencyUs: Int = 0,
    /** False: the test acquires the capture itself (as a screen or a recording). */
    acquired: Boolean = true,
) {
    var nowNs = 0L
    val settings = MutableStateFlow(settings)
    val source = FakeSensorSource(kinds, latencyUs)
    val ring = EventRing(ringCapacity)
    val capture = Capture(
        ring, source, this.settings, CoroutineScope(Dispatchers.Unconfined), MutableStateFlow(calibration),
        reorderWindowNs = reorderWindowNs, nanoTime = { nowNs }, runThread = false, publishIntervalNs = publishIntervalNs,
    ).apply { if (acquired) acquire() }
    private val v = FloatArray(6)

    fun offer(stream: SessionStream, t: Long, vararg values: Float, accuracy: Int = 3): Boolean {
        values.copyInto(v)
        return ring.offer(stream, t, accuracy, v, values.size)
    }

    /** Pumps until the ring is empty. */
    fun drain() {
        while (capture.pump() > 0) Unit
    }

    /** Attaches [recorder] with the current settings, as the recording service does. */
    fun record(recorder: Recorder) {
        capture.attach(recorder, settings.value)
        source.flushCompleted()
        capture.pump()
    }

    /** Stop: the capture hands the recorder everything up to now and ends it. */
    fun stop(recorder: Recorder) {
        capture.detach(recorder)
        source.flushCompleted()
        capture.pump()
        check(recorder.result != null) { "the recorder did not end" }
    }
}
