package dev.motionfusion.app.sensor

import dev.motionfusion.core.event.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.random.Random

class ReorderWindowTest {
    private class Out(val stream: SessionStream, val t: Long, val x: Float, val accuracy: Int, val gap: Boolean)

    private val out = ArrayList<Out>()
    private val sink = EventRing.Consumer { s, t, a, v, o, gap -> out += Out(s, t, v[o], a, gap) }
    private val v = FloatArray(SensorStreams.maxValues)

    private fun ReorderWindow.add(s: SessionStream, t: Long, x: Float = t.toFloat(), accuracy: Int = 3, gap: Boolean = false) {
        v[0] = x
        add(s, t, accuracy, v, 0, gap, sink)
    }

    @Test
    fun `batches of separate sensors come out merged by timestamp, ties in the session reader's order`() {
        val w = ReorderWindow(windowNs = 30)
        // Android: the gyroscope's batch, then the accelerometer's, then the magnetometer's, each in order.
        for (t in 0L until 20L step 5) w.add(SessionStream.GYROSCOPE, t)
        for (t in 0L until 20L step 5) w.add(SessionStream.ACCELEROMETER, t)
        for (t in 0L until 20L step 5) w.add(SessionStream.MAGNETOMETER, t, accuracy = 1)
        assertTrue(out.isEmpty(), "all within the window")
        w.flush(sink)
        assertEquals((0L until 20L step 5).flatMap { listOf(it, it, it) }, out.map { it.t })
        // At equal timestamps accelerometer and magnetometer come before the gyroscope, as SessionReader merges them.
        assertEquals(listOf(SessionStream.ACCELEROMETER, SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE), out.take(3).map { it.stream })
        assertEquals(listOf(3, 1, 3), out.take(3).map { it.accuracy })
        assertEquals(out.map { it.t.toFloat() }, out.map { it.x }, "values travel with their event")
    }

    @Test
    fun `events are held only until one a window newer arrives`() {
        val w = ReorderWindow(windowNs = 10)
        w.add(SessionStream.GYROSCOPE, 100)
        w.add(SessionStream.GYROSCOPE, 105)
        assertEquals(0, out.size)
        w.add(SessionStream.GYROSCOPE, 110)
        assertEquals(listOf(100L), out.map { it.t })
        assertEquals(2, w.size)
    }

    @Test
    fun `shuffled within the window, 100,000 events of seven streams come out sorted and complete`() {
        val w = ReorderWindow(windowNs = 10_000_000L)
        val rnd = Random(3)
        val events = ArrayList<Pair<SessionStream, Long>>()
        var t = 0L
        repeat(100_000) {
            t += rnd.nextLong(1, 200_000)
            events += SensorStreams.all[rnd.nextInt(7)] to t
        }
        // Each stream's events in order; the streams' batches of up to 4 ms handed over in turn.
        val batches = events.groupBy { it.first to it.second / 4_000_000L }.entries.sortedBy { it.key.second }
        for (b in batches.shuffledWithin(rnd)) for ((s, ts) in b.value) w.add(s, ts)
        w.flush(sink)
        assertEquals(events.size, out.size)
        assertEquals(out.map { it.t }.sorted(), out.map { it.t })
        assertEquals(0L, w.late)
    }

    /** Pairs of adjacent batches swapped at random: each stream still in order, the merged stream stepping back by up to 8 ms. */
    private fun <T> List<T>.shuffledWithin(rnd: Random): List<T> {
        val l = toMutableList()
        for (i in 0 until l.size - 1 step 2) if (rnd.nextBoolean()) { val x = l[i]; l[i] = l[i + 1]; l[i + 1] = x }
        return l
    }

    @Test
    fun `an event older than one released is passed on at once and counted late`() {
        val w = ReorderWindow(windowNs = 10)
        w.add(SessionStream.GYROSCOPE, 100)
        w.add(SessionStream.GYROSCOPE, 120)
        assertEquals(listOf(100L), out.map { it.t })
        w.add(SessionStream.ACCELEROMETER, 90)
        assertEquals(listOf(100L, 90L), out.map { it.t })
        assertEquals(1L, w.late)
    }

    @Test
    fun `a full window releases its oldest early, and the gap flag travels with its event`() {
        val w = ReorderWindow(capacity = 4, windowNs = 1_000)
        for (t in 0L until 6L) w.add(SessionStream.GYROSCOPE, t, gap = t == 2L)
        assertEquals(listOf(0L, 1L), out.map { it.t })
        w.flush(sink)
        assertEquals(listOf(false, false, true, false, false, false), out.map { it.gap })
    }

    /**
     * Eight streams at 400 Hz (the magnetometer at 100 Hz) for 60 s, delivered as FIFOs with a
     * 5-s report latency would: each stream's batch whole, at its own phase. The window set up for
     * that latency puts them all in order; narrower, or with the queues of the default size, it
     * passes events on out of order (a queue of 1024 holds 2.6 s of one stream: half a batch).
     */
    @Test
    fun `hardware batches of several seconds, interleaved by sensor, come out in order with the window set for the latency`() {
        val latencyUs = 5_000_000
        val rnd = Random(11)
        val events = ArrayList<Pair<SessionStream, Long>>()
        for (s in SensorStreams.all) {
            val period = if (s == SessionStream.MAGNETOMETER) 10_000_000L else 2_500_000L
            var t = rnd.nextLong(period)
            while (t < 60_000_000_000L) {
                events += s to t
                t += period + rnd.nextLong(-100_000L, 100_000L) // jitter
            }
        }
        val phases = SensorStreams.all.associateWith { if (it.ordinal % 3 == 0) 0L else rnd.nextLong(latencyUs * 1000L) }
        val batches = FifoBatches.of(events, { it.first }, { it.second }, latencyUs * 1000L, { phases.getValue(it) })

        fun run(w: ReorderWindow): ReorderWindow {
            out.clear()
            for (b in batches) for ((s, t) in b.events) w.add(s, t)
            w.flush(sink)
            assertEquals(events.size, out.size)
            return w
        }
        val window = dev.motionfusion.app.fusion.Capture.windowFor(latencyUs)
        val set = run(ReorderWindow(windowNs = window).apply { ensureCapacity(dev.motionfusion.app.fusion.Capture.capacityFor(400.0, window)) })
        assertEquals(0L, set.late, "no event passed on out of order")
        val key = compareBy<Out>({ it.t }, { it.stream.ordinal })
        assertEquals(out.sortedWith(key).map { it.t to it.stream }, out.map { it.t to it.stream })
        assertTrue(window >= latencyUs * 1000L + ReorderWindow.DEFAULT_WINDOW_NS)
        // The mechanism off: the window of unbatched delivery, or queues too small for a batch.
        val narrow = run(ReorderWindow(windowNs = ReorderWindow.DEFAULT_WINDOW_NS).apply { ensureCapacity(1 shl 14) }).late
        val small = run(ReorderWindow(windowNs = window)).late
        println("batched delivery, 5-s latency, ${events.size} events: late with the unbatched window $narrow, with the default queues $small")
        assertTrue(narrow > 10_000)
        assertTrue(small > 0)
    }

    @Test
    fun `growing the queues keeps the events waiting, in order`() {
        val w = ReorderWindow(capacity = 4, windowNs = 1_000)
        for (t in 0L until 3L) w.add(SessionStream.GYROSCOPE, t * 10)
        for (t in 0L until 3L) w.add(SessionStream.ACCELEROMETER, t * 10 + 5)
        w.ensureCapacity(64)
        assertEquals(64, w.capacity)
        for (t in 3L until 40L) w.add(SessionStream.GYROSCOPE, t * 10)
        assertTrue(out.isEmpty(), "nothing released early: the queues grew")
        w.flush(sink)
        assertEquals(out.map { it.t }.sorted(), out.map { it.t })
        assertEquals(43, out.size)
    }
}
