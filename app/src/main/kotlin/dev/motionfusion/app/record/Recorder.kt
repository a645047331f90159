package dev.motionfusion.app.record

import dev.motionfusion.core.session.SessionStream
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.session.ClockAnchor
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicLongArray
import java.util.concurrent.locks.LockSupport

/**
 * The writer side of a recording: one thread drains the [EventRing] into a [SessionSink],
 * runs the Madgwick [filter] on the accelerometer, magnetometer and gyroscope rows in the
 * order they are written (one fused row after each gyroscope row once the filter is
 * initialised, its diagnostics every [diagnosticsIntervalNs]), flushes at least every
 * [flushIntervalNs] and, every [checkpointIntervalNs], adds a wall-clock anchor and fsyncs.
 *
 * The recording ends, and [onEnd] is called once from the writer thread, when
 * - [stop] was called: the queue is closed, drained to the last event, the session finished;
 * - the queue overflowed: everything queued before the overflow is written, then it ends;
 * - [freeBytes] fell below [minFreeBytes]: stopped before the disk fills;
 * - the sink threw: the session is abandoned as it is on disk (the caller repairs it).
 * Nothing is ever skipped in the middle: a recording is always a gap-free prefix of what the
 * sensors delivered.
 */
internal class Recorder(
    private val ring: EventRing,
    private val sink: SessionSink,
    private val filter: MadgwickFilter?,
    private val onEnd: (RecorderResult) -> Unit,
    private val flushIntervalNs: Long = 500_000_000L,
    private val freeBytes: () -> Long = { Long.MAX_VALUE },
    private val minFreeBytes: Long = 0L,
    private val spaceCheckIntervalNs: Long = 2_000_000_000L,
    private val nanoTime: () -> Long = System::nanoTime,
    private val idleParkNs: Long = 2_000_000L,
    /** Filter diagnostics are written at most this often (sensor time): they change slowly. */
    private val diagnosticsIntervalNs: Long = 100_000_000L,
    /** Wall-clock anchors and fsync every [checkpointIntervalNs] when given. */
    private val anchorNow: (() -> ClockAnchor)? = null,
    private val checkpointIntervalNs: Long = 60_000_000_000L,
) {
    private var lastDiagnosticsNs = Long.MIN_VALUE / 2
    private val rows = AtomicLongArray(SessionStream.entries.size)
    @Volatile private var fusedRows = 0L
    @Volatile private var stopRequested = false
    private val ended = CountDownLatch(1)
    private var thread: Thread? = null

    /** The writer thread once started (for tests and diagnostics). */
    internal val writerThread: Thread? get() = thread
    private val q = DoubleArray(4)

    @Volatile var result: RecorderResult? = null
        private set

    /** Raw rows written so far (all streams). Any thread. */
    val rowCount: Long get() = (0 until rows.length()).sumOf { rows.get(it) }

    /** Raw rows written so far, per stream. Any thread. */
    fun rowCount(stream: SessionStream): Long = rows.get(stream.ordinal)

    /** Fused orientation rows written so far. Any thread. */
    val fusedCount: Long get() = fusedRows

    private val consumer = EventRing.Consumer { stream, t, accuracy, values, offset ->
        sink.raw(stream, t, accuracy, values, offset)
        rows.lazySet(stream.ordinal, rows.get(stream.ordinal) + 1)
        if (filter != null) fuse(filter, stream, t, values, offset)
    }

    private fun fuse(filter: MadgwickFilter, stream: SessionStream, t: Long, v: FloatArray, o: Int) {
        when (stream) {
            SessionStream.ACCELEROMETER -> filter.updateAccelerometer(t, v[o].toDouble(), v[o + 1].toDouble(), v[o + 2].toDouble())
            SessionStream.MAGNETOMETER -> filter.updateMagnetometer(t, v[o].toDouble(), v[o + 1].toDouble(), v[o + 2].toDouble())
            SessionStream.GYROSCOPE -> {
                filter.updateGyroscope(t, v[o].toDouble(), v[o + 1].toDouble(), v[o + 2].toDouble())
                if (filter.isInitialised) {
                    filter.orientationInto(q, 0)
                    sink.fused(t, q, 0)
                    fusedRows++
                    if (t - lastDiagnosticsNs >= diagnosticsIntervalNs || t < lastDiagnosticsNs) {
                        lastDiagnosticsNs = t
                        val d = filter.diagnostics()
                        sink.diagnostics(t, d.gyroBias.x, d.gyroBias.y, d.gyroBias.z, d.atRest, d.magneticDisturbance, d.accelerometerRejected)
                    }
                }
            }
            else -> Unit
        }
    }

    /**
     * Writes up to [max] queued events on the calling thread, exactly as the writer loop does;
     * for the benchmark (a recorder that is not started). Returns how many were written.
     */
    fun writeQueued(max: Int): Int = ring.drain(consumer, max)

    /** Starts the writer thread. */
    fun start() {
        check(thread == null) { "already started" }
        thread = Thread(::run, "session-writer").apply {
            priority = Thread.NORM_PRIORITY + 1
            start()
        }
    }

    /**
     * Asks the writer to write what is queued, finish the session and end. Returns at once.
     * Call it after the producer has stopped offering (listeners unregistered, sensor thread
     * joined): the queue is closed here, so a later offer is refused, not written.
     */
    fun stop() {
        ring.close()
        stopRequested = true
        thread?.let(LockSupport::unpark)
    }

    /** Waits for the end; true if it came within [timeoutMs]. */
    fun awaitEnd(timeoutMs: Long): Boolean = ended.await(timeoutMs, TimeUnit.MILLISECONDS)

    private fun run() {
        val end: RecordingEnd = try {
            loop()
        } catch (e: Exception) {
            ring.close()
            val failed = RecordingEnd.WriteFailed(e.message ?: e.javaClass.simpleName)
            sink.abandon(failed)
            failed
        }
        val r = RecorderResult(end, LongArray(rows.length()) { rows.get(it) }, fusedRows, ring.refused)
        result = r
        try {
            onEnd(r)
        } finally {
            ended.countDown()
        }
    }

    private fun loop(): RecordingEnd {
        var lastFlush = nanoTime()
        var lastCheckpoint = lastFlush
        var lastSpaceCheck = 0L
        var spaceChecked = false
        while (true) {
            val n = ring.drain(consumer, DRAIN_BATCH)
            val now = nanoTime()
            if (now - lastFlush >= flushIntervalNs) {
                sink.flush()
                lastFlush = now
            }
            if (anchorNow != null && now - lastCheckpoint >= checkpointIntervalNs) {
                sink.checkpoint(anchorNow.invoke())
                lastCheckpoint = now
            }
            if (minFreeBytes > 0 && (!spaceChecked || now - lastSpaceCheck >= spaceCheckIntervalNs)) {
                spaceChecked = true
                lastSpaceCheck = now
                val free = freeBytes()
                if (free < minFreeBytes) {
                    ring.close()
                    ring.drain(consumer) // what is queued is small next to the margin
                    return finishWith(RecordingEnd.StorageLow(free))
                }
            }
            if (ring.size == 0) {
                val overflowAt = ring.overflowTimestampNs
                if (overflowAt != null) return finishWith(RecordingEnd.QueueOverflow(overflowAt))
                if (stopRequested) {
                    // The producer has stopped (see [stop]); pick up anything it published last.
                    ring.drain(consumer)
                    return finishWith(RecordingEnd.Stopped)
                }
            }
            if (n == 0) LockSupport.parkNanos(idleParkNs)
        }
    }

    private fun finishWith(end: RecordingEnd): RecordingEnd {
        sink.finish(end)
        return end
    }

    private companion object {
        const val DRAIN_BATCH = 4096
    }
}

/** How a recording ended and what it holds. */
internal data class RecorderResult(
    val end: RecordingEnd,
    /** Raw rows written per stream, indexed by [SessionStream.ordinal]. */
    val rowsPerStream: LongArray,
    val fusedRows: Long,
    /** Events the queue refused (after an overflow or after stop): never written. */
    val refused: Long,
) {
    val rows: Long get() = rowsPerStream.sum()
}
