package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.FifoBatches
import dev.motionfusion.app.sensor.ReorderWindow
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.MadgwickFilter
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import dev.motionfusion.app.fusion.Capture
import dev.motionfusion.app.fusion.CaptureTap
import dev.motionfusion.app.fusion.RawListener
import dev.motionfusion.app.fusion.TapEnd

/**
 * Hardware batching while nothing is on screen: the capture's reorder window follows the report
 * latency the sensors are registered with, a screen gets the events at once again (and the FIFOs
 * flushed), and a recording's start and end wait for the FIFOs' events.
 */
class CaptureBatchingTest {
    private val latencyUs = 2_000_000
    private val base = ReorderWindow.DEFAULT_WINDOW_NS
    private val wide = Capture.windowFor(latencyUs, base)

    /** Events seen by a raw reader of the capture, in the order it saw them. */
    private class Seen : RawListener {
        val events = ArrayList<Pair<Long, SessionStream>>()
        override fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int) {
            events += timestampNs to stream
        }

        fun inOrder() = events == events.sortedWith(compareBy({ it.first }, { it.second.ordinal }))
    }

    /** A tap that keeps the timestamps it was given. */
    private class Tap : CaptureTap {
        val times = ArrayList<Long>()
        var ended: TapEnd? = null
        override fun raw(stream: SessionStream, timestampNs: Long, accuracy: Int, values: FloatArray, offset: Int) {
            times += timestampNs
        }
        override fun stepped(timestampNs: Long, filter: MadgwickFilter) = Unit
        override fun afterBatch(nowNs: Long) = true
        override fun end(end: TapEnd) {
            ended = end
        }
    }

    @Test
    fun `the window widens for the latency only while nothing is on screen, and narrows once the flushed FIFOs arrived`() {
        val c = TestCapture(latencyUs = latencyUs, acquired = false)
        c.source.maxEventsPerSecond = 500.0
        c.capture.acquire() // a recording: nothing on screen
        c.capture.pump()
        assertEquals(wide, c.capture.reorderWindowNs)
        assertEquals(base + 2_500_000_000L, wide, "the latency and a quarter, plus the unbatched window")
        // Sized when the latency was chosen: a batch of every stream at the rate, twice over.
        assertEquals(Capture.capacityFor(500.0, wide), c.capture.reorderCapacity)
        assertEquals(2530, c.capture.reorderCapacity) // 500 Hz × 2.53 s × 2
        assertEquals(latencyUs, c.capture.reportLatencyUs)
        assertFalse(c.source.immediate)

        c.capture.acquire(onScreen = true) // the live screen comes back
        assertTrue(c.source.immediate, "events at once for the screen")
        assertEquals(1, c.source.flushRequests, "the FIFOs are asked for what they hold")
        c.nowNs += 100_000_000L
        c.capture.pump()
        assertEquals(wide, c.capture.reorderWindowNs, "narrowed only once the flushed events are in")
        c.source.flushCompleted()
        c.capture.pump()
        assertEquals(base, c.capture.reorderWindowNs)

        c.capture.release(onScreen = true)
        assertFalse(c.source.immediate)
        c.capture.pump()
        assertEquals(wide, c.capture.reorderWindowNs)

        // A device that never says its flush completed: narrowed after as long as a batch can take.
        c.capture.acquire(onScreen = true)
        c.capture.pump()
        assertEquals(wide, c.capture.reorderWindowNs)
        c.nowNs += wide
        c.capture.pump()
        assertEquals(base, c.capture.reorderWindowNs)
    }

    @Test
    fun `without a FIFO nothing changes when screens come and go`() {
        val c = TestCapture(latencyUs = 0, acquired = false)
        c.capture.acquire()
        c.capture.pump()
        assertEquals(base, c.capture.reorderWindowNs)
        assertEquals(ReorderWindow.DEFAULT_CAPACITY, c.capture.reorderCapacity)
        c.capture.acquire(onScreen = true)
        c.capture.pump()
        c.capture.release(onScreen = true)
        c.capture.pump()
        assertEquals(base, c.capture.reorderWindowNs)
        assertEquals(0, c.source.flushRequests)
    }

    /** Accelerometer and gyroscope at 200 Hz, magnetometer at 100 Hz, from [fromNs] until [toNs]. */
    private fun events(fromNs: Long, toNs: Long): List<Pair<SessionStream, Long>> {
        val out = ArrayList<Pair<SessionStream, Long>>()
        var t = fromNs
        while (t < toNs) {
            out += SessionStream.ACCELEROMETER to t
            out += SessionStream.GYROSCOPE to t + 1_000_000L
            if ((t / 5_000_000L) % 2 == 0L) out += SessionStream.MAGNETOMETER to t + 2_000_000L
            t += 5_000_000L
        }
        return out
    }

    private fun TestCapture.deliver(batch: List<Pair<SessionStream, Long>>) {
        for ((s, t) in batch) offer(s, t, 0.1f, 0.2f, 9.8f)
    }

    @Test
    fun `a screen coming back mid-batch gets the FIFOs' events in order, none late`() {
        val c = TestCapture(latencyUs = latencyUs, acquired = false)
        val seen = Seen()
        c.capture.listen(seen)
        c.capture.acquire()
        val l = latencyUs * 1000L
        val phase = mapOf(SessionStream.ACCELEROMETER to 300_000_000L, SessionStream.GYROSCOPE to 700_000_000L, SessionStream.MAGNETOMETER to 1_300_000_000L)
        // 10 s batched, the capture pumping after each sensor's batch, as its thread would.
        val batched = FifoBatches.of(events(0, 10_000_000_000L), { it.first }, { it.second }, l, { phase.getValue(it) })
            .filter { it.deliveredNs <= 10_000_000_000L }
        for (b in batched) {
            c.nowNs = b.deliveredNs
            c.deliver(b.events)
            c.capture.pump()
        }
        // The screen comes back: each FIFO's rest arrives, one sensor after another, the capture pumping between.
        c.capture.acquire(onScreen = true)
        val delivered = batched.flatMap { it.events }.toSet()
        val rest = events(0, 10_000_000_000L).filter { it !in delivered }
        assertTrue(rest.size > 600, "${rest.size} events in the FIFOs") // 1.7 s of the accelerometer, 1.3 s of the gyroscope, 0.7 s of the magnetometer
        for (s in listOf(SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER)) {
            c.deliver(rest.filter { it.first == s })
            c.nowNs += 2_000_000L
            c.capture.pump()
        }
        c.source.flushCompleted()
        // Then every event as it comes.
        for (e in events(10_000_000_000L, 11_000_000_000L)) {
            c.deliver(listOf(e))
            c.nowNs = e.second
            c.capture.pump()
        }
        assertEquals(base, c.capture.reorderWindowNs)
        assertEquals(0L, c.capture.lateEvents)
        assertTrue(seen.inOrder(), "the live filter's readers saw the events in timestamp order")
        // And the screen is current: only the last 30 ms (the unbatched window) are still held.
        assertTrue(seen.events.last().first >= 11_000_000_000L - base - 5_000_000L)
    }

    @Test
    fun `a recording's end waits for the FIFOs' events, at most a second`() {
        val c = TestCapture(latencyUs = latencyUs)
        val tap = Tap()
        c.capture.attach(tap, c.settings.value)
        assertEquals(1, c.source.flushRequests, "the start waits for what was batched before it")
        c.source.flushCompleted()
        c.capture.pump()
        c.deliver(events(0, 1_000_000_000L))
        c.capture.pump()
        c.capture.detach(tap)
        c.capture.pump()
        assertNull(tap.ended, "still waiting for the FIFOs")
        c.deliver(events(1_000_000_000L, 1_500_000_000L)) // what the FIFOs held at the stop
        c.source.flushCompleted()
        c.capture.pump()
        assertEquals(TapEnd.Detached, tap.ended)
        assertEquals(events(0, 1_500_000_000L).map { it.second }.sorted(), tap.times)

        // A device that does not report the flush: the stop goes ahead after FLUSH_TIMEOUT_NS.
        val tap2 = Tap()
        c.capture.attach(tap2, c.settings.value)
        c.source.flushCompleted()
        c.capture.pump()
        c.capture.detach(tap2)
        c.capture.pump()
        assertNull(tap2.ended)
        c.nowNs += Capture.FLUSH_TIMEOUT_NS
        c.capture.pump()
        assertEquals(TapEnd.Detached, tap2.ended)
    }
}
