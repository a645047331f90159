package dev.motionfusion.app.record

import dev.motionfusion.app.fusion.CaptureTap
import dev.motionfusion.app.fusion.TapEnd
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.Marker
import dev.motionfusion.core.session.SessionMarkers
import dev.motionfusion.core.sync.ClockExchange
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.atomic.AtomicLongArray

/**
 * The writer side of a recording, attached to the capture ([CaptureTap]): on the capture
 * thread it writes each ordered sensor event into a [SessionSink], one fused row after each
 * gyroscope event that stepped the live filter (the one filter of the app, so orientation.csv is
 * what was on screen), its diagnostics every [diagnosticsIntervalNs]; after each batch it
 * flushes at least every [flushIntervalNs] and, every [checkpointIntervalNs], adds a wall-clock
 * anchor and fsyncs.
 *
 * Markers ([mark], from any thread) are written by the same sink after the next batch, so the
 * one writer of the session stays on the capture thread.
 *
 * The recording ends, and [onEnd] is called once from the capture thread, when
 * - the capture detached it (the user stopped, or a limit of [stopBecause] was reached):
 *   everything up to then written, the session finished with that reason;
 * - events were lost (the ring was full): everything before the loss is written, then it ends;
 * - [freeBytes] fell below [minFreeBytes]: stopped before the disk fills;
 * - the sink threw: the session is abandoned as it is on disk (the caller repairs it).
 * Nothing is ever skipped in the middle: a recording is always a gap-free prefix of what the
 * sensors delivered.
 */
internal class Recorder(
    private val sink: SessionSink,
    private val onEnd: (RecorderResult) -> Unit,
    private val flushIntervalNs: Long = 500_000_000L,
    private val freeBytes: () -> Long = { Long.MAX_VALUE },
    private val minFreeBytes: Long = 0L,
    private val spaceCheckIntervalNs: Long = 2_000_000_000L,
    /** Filter diagnostics are written at most this often (sensor time): they change slowly. */
    private val diagnosticsIntervalNs: Long = 100_000_000L,
    /** Wall-clock anchors and fsync every [checkpointIntervalNs] when given. */
    private val anchorNow: (() -> ClockAnchor)? = null,
    private val checkpointIntervalNs: Long = 60_000_000_000L,
    /** The raw streams written (null: all); the others are left out. */
    streams: Set<SessionStream>? = null,
    /** No sample before this sensor time is written (a laptop's remote start at an instant: docs/STREAMING.md). */
    private val notBeforeNs: Long = Long.MIN_VALUE,
) : CaptureTap {
    private val writes = BooleanArray(SessionStream.entries.size) { streams == null || SessionStream.entries[it] in streams }
    private var lastDiagnosticsNs = Long.MIN_VALUE / 2
    private val rows = AtomicLongArray(SessionStream.entries.size)
    @Volatile private var fusedRows = 0L
    private val q = DoubleArray(4)
    private var started = false
    private var lastFlush = 0L
    private var lastCheckpoint = 0L
    private var lastSpaceCheck = 0L
    private var spaceChecked = false

    @Volatile var result: RecorderResult? = null
        private set

    private val pendingMarkers = ConcurrentLinkedQueue<Marker>()
    private val pendingClock = ConcurrentLinkedQueue<Pair<ClockExchange, String>>()

    /** A whole clock exchange with the laptop clock [laptopClock]; written to clock.csv with the next batch. Any thread. */
    fun clockExchange(e: ClockExchange, laptopClock: String) {
        pendingClock += e to laptopClock
    }
    private val markerList = CopyOnWriteArrayList<Marker>()
    @Volatile private var stopReason: RecordingEnd = RecordingEnd.Stopped

    /** Markers set so far, as the session stores them (for the live plot). Any thread. */
    val markers: List<Marker> get() = markerList

    /** Marks [timestampNs] (sensor clock) with [label]; written with the next batch. Any thread. */
    fun mark(timestampNs: Long, label: String) {
        val m = Marker(timestampNs, SessionMarkers.label(label))
        markerList += m
        pendingMarkers += m
    }

    /** The reason the session will end with when the capture detaches it (default: stopped by the user). Any thread, before detaching. */
    fun stopBecause(end: RecordingEnd) {
        stopReason = end
    }

    private fun writeMarkers() {
        while (true) {
            val m = pendingMarkers.poll() ?: break
            sink.marker(m.timestampNs, m.label)
        }
        while (true) {
            val (e, link) = pendingClock.poll() ?: return
            sink.clockExchange(e, link)
        }
    }

    /** Raw rows written so far (all streams). Any thread. */
    val rowCount: Long get() = (0 until rows.length()).sumOf { rows.get(it) }

    /** Raw rows written so far, per stream. Any thread. */
    fun rowCount(stream: SessionStream): Long = rows.get(stream.ordinal)

    /** Fused orientation rows written so far. Any thread. */
    val fusedCount: Long get() = fusedRows

    override fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int) {
        if (!writes[stream.ordinal] || timestampNs < notBeforeNs) return
        sink.raw(stream, timestampNs, accuracy, values, offset)
        rows.lazySet(stream.ordinal, rows.get(stream.ordinal) + 1)
    }

    override fun stepped(timestampNs: Long, filter: MadgwickFilter) {
        if (timestampNs < notBeforeNs) return
        filter.orientationInto(q, 0)
        sink.fused(timestampNs, q, 0)
        fusedRows++
        if (timestampNs - lastDiagnosticsNs >= diagnosticsIntervalNs || timestampNs < lastDiagnosticsNs) {
            lastDiagnosticsNs = timestampNs
            val d = filter.diagnostics()
            sink.diagnostics(timestampNs, d.gyroBias.x, d.gyroBias.y, d.gyroBias.z, d.atRest, d.magneticDisturbance, d.accelerometerRejected)
        }
    }

    override fun afterBatch(nowNs: Long): Boolean {
        writeMarkers()
        if (!started) {
            started = true
            lastFlush = nowNs
            lastCheckpoint = nowNs
        }
        if (nowNs - lastFlush >= flushIntervalNs) {
            sink.flush()
            lastFlush = nowNs
        }
        if (anchorNow != null && nowNs - lastCheckpoint >= checkpointIntervalNs) {
            sink.checkpoint(anchorNow.invoke())
            lastCheckpoint = nowNs
        }
        if (minFreeBytes > 0 && (!spaceChecked || nowNs - lastSpaceCheck >= spaceCheckIntervalNs)) {
            spaceChecked = true
            lastSpaceCheck = nowNs
            val free = freeBytes()
            if (free < minFreeBytes) {
                finishWith(RecordingEnd.StorageLow(free))
                return false
            }
        }
        return true
    }

    override fun end(end: TapEnd) {
        when (end) {
            TapEnd.Detached -> finishWith(stopReason)
            is TapEnd.EventsLost -> finishWith(RecordingEnd.QueueOverflow(end.atTimestampNs))
            is TapEnd.Failed -> failed(end.error)
        }
    }

    private fun finishWith(end: RecordingEnd) {
        try {
            writeMarkers()
            sink.finish(end)
        } catch (e: Exception) {
            failed(e)
            return
        }
        done(end)
    }

    private fun failed(e: Exception) {
        val failed = RecordingEnd.WriteFailed(e.message ?: e.javaClass.simpleName)
        sink.abandon(failed)
        done(failed)
    }

    private fun done(end: RecordingEnd) {
        val r = RecorderResult(end, LongArray(rows.length()) { rows.get(it) }, fusedRows)
        result = r
        onEnd(r)
    }
}

/** How a recording ended and what it holds. */
internal data class RecorderResult(
    val end: RecordingEnd,
    /** Raw rows written per stream, indexed by [SessionStream.ordinal]. */
    val rowsPerStream: LongArray,
    val fusedRows: Long,
) {
    val rows: Long get() = rowsPerStream.sum()
}
