package dev.motionfusion.app.record

import dev.motionfusion.core.session.SessionStream
import dev.motionfusion.core.filter.MadgwickFilter
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertInstanceOf
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.concurrent.CopyOnWriteArrayList

class RecorderTest {
    private val v3 = floatArrayOf(0f, 0f, 9.81f)
    private val ends = CopyOnWriteArrayList<RecorderResult>()

    private fun recorder(ring: EventRing, sink: SessionSink, filter: MadgwickFilter? = null, flushNs: Long = 500_000_000L,
                         free: () -> Long = { Long.MAX_VALUE }, minFree: Long = 0) =
        Recorder(ring, sink, filter, onEnd = { ends += it }, flushIntervalNs = flushNs, freeBytes = free, minFreeBytes = minFree)

    @Test
    fun `stop writes every queued event, finishes the session and ends once`() {
        val ring = EventRing(1 shl 10)
        val sink = MemorySink()
        val r = recorder(ring, sink)
        r.start()
        repeat(500) { ring.offer(SensorStreams.all[it % 7], it.toLong(), 3, floatArrayOf(it.toFloat(), 0f, 0f, 0f, 0f, 0f), 6) }
        r.stop()
        assertTrue(r.awaitEnd(5_000))
        assertEquals((0L until 500L).toList(), sink.times)
        assertEquals(RecordingEnd.Stopped, sink.finished)
        assertFalse(sink.abandoned)
        assertEquals(1, ends.size)
        assertEquals(500L, ends[0].rows)
        assertEquals(RecordingEnd.Stopped, ends[0].end)
        assertFalse(ring.offer(SessionStream.GYROSCOPE, 999, 3, v3, 3), "nothing is accepted after stop")
    }

    @Test
    fun `flushes at least every interval while recording`() {
        val ring = EventRing(1 shl 10)
        val sink = MemorySink()
        val r = recorder(ring, sink, flushNs = 50_000_000L)
        r.start()
        val t0 = System.nanoTime()
        var i = 0L
        while (System.nanoTime() - t0 < 600_000_000L) {
            ring.offer(SessionStream.ACCELEROMETER, i++, 3, v3, 3)
            Thread.sleep(1)
        }
        r.stop()
        assertTrue(r.awaitEnd(5_000))
        assertTrue(sink.flushes.size >= 8, "flushes: ${sink.flushes.size}")
        val gaps = sink.flushes.zipWithNext { a, b -> b - a }
        assertTrue(gaps.max() < 300_000_000L, "longest time between flushes ${gaps.max() / 1e6} ms")
    }

    @Test
    fun `adds a wall-clock anchor and syncs every checkpoint interval`() {
        val ring = EventRing(1 shl 10)
        val sink = MemorySink()
        var k = 0L
        val r = Recorder(ring, sink, null, onEnd = { ends += it }, anchorNow = { k++; dev.motionfusion.core.session.ClockAnchor(1_000L * k, k) },
            checkpointIntervalNs = 50_000_000L)
        r.start()
        Thread.sleep(400)
        r.stop()
        assertTrue(r.awaitEnd(5_000))
        assertTrue(sink.checkpoints.size in 4..9, "${sink.checkpoints.size} checkpoints")
        assertEquals(sink.checkpoints.map { it.elapsedRealtimeNs }.sorted(), sink.checkpoints.map { it.elapsedRealtimeNs })
    }

    @Test
    fun `a write failure stops cleanly with everything before it and a message`() {
        val ring = EventRing(1 shl 10)
        val sink = MemorySink(failAfterRows = 123)
        val r = recorder(ring, sink)
        r.start()
        repeat(300) { ring.offer(SessionStream.GYROSCOPE, it.toLong(), 3, v3, 3) }
        assertTrue(r.awaitEnd(5_000))
        assertEquals((0L until 123L).toList(), sink.times, "every row before the failure, in order")
        assertTrue(sink.abandoned)
        assertNull(sink.finished)
        val end = ends.single()
        assertInstanceOf(RecordingEnd.WriteFailed::class.java, end.end)
        assertEquals("No space left on device", (end.end as RecordingEnd.WriteFailed).message)
        assertEquals(123L, end.rows)
        assertFalse(ring.offer(SessionStream.GYROSCOPE, 1_000, 3, v3, 3), "sensors are refused after the failure")
    }

    @Test
    fun `a full queue ends the recording after writing everything queued before the overflow`() {
        val ring = EventRing(64)
        val gate = Object()
        var open = false
        // A sink that blocks until the test has overflowed the queue: storage that cannot keep up.
        val sink = object : SessionSink by MemorySink() {
            val times = ArrayList<Long>()
            override fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int) {
                synchronized(gate) { while (!open) gate.wait() }
                times += timestampNs
            }
        }
        val r = recorder(ring, sink)
        r.start()
        var offered = 0L
        while (ring.offer(SessionStream.GYROSCOPE, offered, 3, v3, 3)) offered++
        synchronized(gate) { open = true; gate.notifyAll() }
        assertTrue(r.awaitEnd(5_000))
        val end = ends.single()
        assertEquals(RecordingEnd.QueueOverflow(offered), end.end)
        assertEquals((0L until offered).toList(), sink.times, "a gap-free prefix")
        assertTrue(offered >= 64)
    }

    @Test
    fun `low free space stops before the disk is full`() {
        val ring = EventRing(1 shl 10)
        val sink = MemorySink()
        val free = java.util.concurrent.atomic.AtomicLong(100L * 1024 * 1024)
        val r = Recorder(ring, sink, null, onEnd = { ends += it }, freeBytes = { free.get() }, minFreeBytes = 32L * 1024 * 1024,
            spaceCheckIntervalNs = 10_000_000L)
        r.start()
        repeat(50) { ring.offer(SessionStream.ACCELEROMETER, it.toLong(), 3, v3, 3) }
        Thread.sleep(100)
        free.set(10L * 1024 * 1024)
        assertTrue(r.awaitEnd(5_000))
        assertEquals(RecordingEnd.StorageLow(10L * 1024 * 1024), ends.single().end)
        assertEquals(50, sink.times.size)
        assertEquals(RecordingEnd.StorageLow(10L * 1024 * 1024), sink.finished)
    }

    @Test
    fun `the filter runs on the written rows and writes one fused row per gyroscope row`() {
        val ring = EventRing(1 shl 12)
        val sink = MemorySink()
        val r = recorder(ring, sink, MadgwickFilter())
        r.start()
        var t = 1_000_000_000L
        repeat(1000) {
            ring.offer(SessionStream.ACCELEROMETER, t, 3, floatArrayOf(0f, 0f, 9.81f), 3)
            ring.offer(SessionStream.MAGNETOMETER, t + 1, 3, floatArrayOf(0f, 22f, -40f), 3)
            ring.offer(SessionStream.GYROSCOPE, t + 2, 3, floatArrayOf(0f, 0f, 0f), 3)
            ring.offer(SessionStream.ROTATION_VECTOR, t + 3, 3, floatArrayOf(0f, 0f, 0f, 1f, 0.1f), 5)
            t += 5_000_000L
        }
        r.stop()
        assertTrue(r.awaitEnd(5_000))
        assertEquals(4000, sink.times.size)
        val gyroTimes = sink.times.filterIndexed { i, _ -> sink.streams[i] == SessionStream.GYROSCOPE }
        // The first gyroscope sample initialises the filter; every later one steps it and writes a row.
        assertEquals(gyroTimes.drop(1), sink.fusedTimes.drop(sink.fusedTimes.size - gyroTimes.size + 1))
        assertTrue(sink.fusedTimes.size >= 999)
        assertEquals(sink.fusedTimes.size.toLong(), ends.single().fusedRows)
        // Flat, top towards magnetic north: the identity in ENU, |w| = 1 (q and −q are the same rotation).
        assertEquals(1.0, kotlin.math.abs(sink.fusedW.last()), 1e-3)
        // Diagnostics every 100 ms of sensor time: 5 s of data gives about 50 rows.
        assertTrue(sink.diagnosticTimes.size in 45..55, "${sink.diagnosticTimes.size} diagnostics rows")
    }
}
