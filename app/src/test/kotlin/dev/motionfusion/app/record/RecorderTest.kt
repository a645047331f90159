package dev.motionfusion.app.record

import dev.motionfusion.app.live.TestCapture
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.event.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.atomic.AtomicLong

/** The recorder attached to the capture, step by step with a fake clock (no threads, no sleeping). */
class RecorderTest {
    private val ends = CopyOnWriteArrayList<RecorderResult>()
    private val c = TestCapture()

    private fun recorder(sink: SessionSink, flushNs: Long = 500_000_000L, free: () -> Long = { Long.MAX_VALUE }, minFree: Long = 0,
                         anchorNow: (() -> ClockAnchor)? = null, checkpointNs: Long = 60_000_000_000L) =
        Recorder(sink, onEnd = { ends += it }, flushIntervalNs = flushNs, freeBytes = free, minFreeBytes = minFree,
            spaceCheckIntervalNs = 10_000_000L, anchorNow = anchorNow, checkpointIntervalNs = checkpointNs)

    @Test
    fun `stop writes every event up to it, in timestamp order, finishes the session and ends once`() {
        val sink = MemorySink()
        val r = recorder(sink)
        c.record(r)
        repeat(500) { c.offer(SensorStreams.all[it % 7], it * 1_000_000L, it.toFloat(), 0f, 0f, 0f, 0f, 0f) }
        c.drain()
        c.stop(r)
        assertEquals((0L until 500L).map { it * 1_000_000L }, sink.times)
        assertEquals(RecordingEnd.Stopped, sink.finished)
        assertFalse(sink.abandoned)
        assertEquals(1, ends.size)
        assertEquals(500L, ends[0].rows)
        assertEquals(RecordingEnd.Stopped, ends[0].end)
        // Later events reach the live screen only.
        c.offer(SessionStream.GYROSCOPE, 999_000_000L, 0f, 0f, 0f)
        c.drain()
        assertEquals(500, sink.times.size)
    }

    @Test
    fun `flushes at least every interval of the clock while recording`() {
        val sink = MemorySink(clock = { c.nowNs })
        val r = recorder(sink, flushNs = 50_000_000L)
        c.record(r)
        for (i in 0 until 600) {
            c.nowNs = i * 1_000_000L
            c.offer(SessionStream.ACCELEROMETER, i * 1_000_000L, 0f, 0f, 9.81f)
            c.capture.pump()
        }
        c.stop(r)
        assertTrue(sink.flushes.size in 11..12, "flushes: ${sink.flushes.size}")
        assertEquals(50_000_000L, sink.flushes.zipWithNext { a, b -> b - a }.max())
    }

    @Test
    fun `adds a wall-clock anchor (which syncs) every checkpoint interval`() {
        val sink = MemorySink()
        var k = 0L
        val r = recorder(sink, anchorNow = { k++; ClockAnchor(1_000L * k, k) }, checkpointNs = 50_000_000L)
        c.record(r)
        for (i in 0..400) {
            c.nowNs = i * 1_000_000L
            c.capture.pump()
        }
        c.stop(r)
        assertEquals(8, sink.checkpoints.size)
        assertEquals((1L..8L).toList(), sink.checkpoints.map { it.elapsedRealtimeNs })
    }

    @Test
    fun `a write failure stops cleanly with everything before it and a message, and the live screen goes on`() {
        val sink = MemorySink(failAfterRows = 123)
        val r = recorder(sink)
        c.record(r)
        repeat(300) { c.offer(SessionStream.GYROSCOPE, it * 1_000_000L, 0f, 0f, 0f) }
        c.drain()
        c.capture.detach(r)
        c.capture.pump()
        assertEquals((0L until 123L).map { it * 1_000_000L }, sink.times, "every row before the failure, in order")
        assertTrue(sink.abandoned)
        assertNull(sink.finished)
        val end = ends.single()
        assertInstanceOf(RecordingEnd.WriteFailed::class.java, end.end)
        assertEquals("No space left on device", (end.end as RecordingEnd.WriteFailed).message)
        assertEquals(123L, end.rows)
        c.nowNs += 1_000_000_000L
        c.capture.pump() // quiet: the reorder window is emptied
        assertEquals(300L, c.capture.state.value.sensors[dev.motionfusion.app.sensor.SensorKind.GYROSCOPE]!!.samples)
    }

    @Test
    fun `a full ring ends the recording after writing everything before the loss`() {
        val small = TestCapture(ringCapacity = 64)
        val sink = MemorySink()
        val r = recorder(sink)
        small.record(r)
        var offered = 0L
        while (small.offer(SessionStream.GYROSCOPE, offered * 1_000_000L, 0f, 0f, 0f)) offered++
        assertEquals(64L, offered)
        small.offer(SessionStream.GYROSCOPE, (offered + 1) * 1_000_000L, 0f, 0f, 0f) // refused: the ring is full
        small.capture.pump()
        assertTrue(small.offer(SessionStream.GYROSCOPE, (offered + 2) * 1_000_000L, 0f, 0f, 0f), "accepted, after a gap")
        small.drain()
        small.capture.detach(r)
        small.capture.pump()
        val end = ends.single()
        assertEquals(RecordingEnd.QueueOverflow((offered + 2) * 1_000_000L), end.end)
        assertEquals((0L until offered).map { it * 1_000_000L }, sink.times, "a gap-free prefix")
    }

    @Test
    fun `low free space stops before the disk is full`() {
        val sink = MemorySink()
        val free = AtomicLong(100L * 1024 * 1024)
        val r = recorder(sink, free = { free.get() }, minFree = 32L * 1024 * 1024)
        c.record(r)
        repeat(50) { c.offer(SessionStream.ACCELEROMETER, it * 1_000_000L, 0f, 0f, 9.81f) }
        c.drain()
        free.set(10L * 1024 * 1024)
        c.nowNs += 20_000_000L
        c.capture.pump()
        assertEquals(RecordingEnd.StorageLow(10L * 1024 * 1024), ends.single().end)
        // It stops at once: the rows released so far (the last 30 ms were still in the reorder window), a gap-free prefix.
        assertEquals((0L until 20L).map { it * 1_000_000L }, sink.times)
        assertEquals(RecordingEnd.StorageLow(10L * 1024 * 1024), sink.finished)
    }

    @Test
    fun `the live filter's output is written, one fused row per gyroscope step, diagnostics ten times a second`() {
        val sink = MemorySink()
        val r = recorder(sink)
        c.record(r)
        var t = 1_000_000_000L
        repeat(1000) {
            c.offer(SessionStream.ACCELEROMETER, t, 0f, 0f, 9.81f)
            c.offer(SessionStream.MAGNETOMETER, t + 1, 0f, 22f, -40f)
            c.offer(SessionStream.GYROSCOPE, t + 2, 0f, 0f, 0f)
            c.offer(SessionStream.ROTATION_VECTOR, t + 3, 0f, 0f, 0f, 1f, 0.1f)
            t += 5_000_000L
            if (it % 100 == 0) c.drain()
        }
        c.drain()
        c.stop(r)
        assertEquals(4000, sink.times.size)
        val gyroTimes = sink.times.filterIndexed { i, _ -> sink.streams[i] == SessionStream.GYROSCOPE }
        // The first gyroscope sample initialises the filter; every later one steps it and writes a row.
        assertEquals(gyroTimes.drop(1), sink.fusedTimes.drop(sink.fusedTimes.size - gyroTimes.size + 1))
        assertTrue(sink.fusedTimes.size >= 999)
        assertEquals(sink.fusedTimes.size.toLong(), ends.single().fusedRows)
        // Flat, top towards magnetic north: the identity in ENU, |w| = 1 (q and −q are the same rotation).
        assertEquals(1.0, kotlin.math.abs(sink.fusedW.last()), 1e-3)
        val live = c.capture.state.value.orientation!!
        assertEquals(kotlin.math.abs(live.w), kotlin.math.abs(sink.fusedW.last()), 1e-12, "what is written is what the screen shows")
        // Diagnostics every 100 ms of sensor time: 5 s of data gives about 50 rows.
        assertTrue(sink.diagnosticTimes.size in 45..55, "${sink.diagnosticTimes.size} diagnostics rows")
    }
}
