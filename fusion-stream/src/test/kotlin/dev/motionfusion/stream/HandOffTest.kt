package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.stream.StreamMessage
import java.util.Collections
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * The send loop of the server and the UDP push ([HandOff]): bounded, never blocking the capture thread, in order, and
 * ended by stop even while it waits. No sleep: the test waits on latches and on the sender's end.
 */
class HandOffTest {
    @Test
    fun `a full queue drops and counts what does not fit, the sender gets the rest in order, each with its sample time`() {
        val got = Collections.synchronizedList(ArrayList<Pair<StreamMessage, Long>>())
        val all = CountDownLatch(16)
        val h = HandOff(16, "test-sender") { m, t -> got += m to t; all.countDown() }
        // The sender not started yet: the queue fills at its bound and the rest is dropped, the caller never waits.
        val offered = ArrayList<StreamMessage>()
        for (k in 0 until 20) {
            val t = 1_000L + k
            if (k % 2 == 0) {
                val v = floatArrayOf(k.toFloat(), 0f, 1f, 99f) // one value more than a gyroscope has: cut to three
                h.sample(SessionStream.GYROSCOPE, t, v, 3)
                v[0] = -1f // copied when handed off
                offered += StreamMessage.Sample(SessionStream.GYROSCOPE, t, floatArrayOf(k.toFloat(), 0f, 1f), 3)
            } else {
                h.orientation(t, 1.0, 0.0, 0.0, k.toDouble())
                offered += StreamMessage.Orientation(t, 1.0, 0.0, 0.0, k.toDouble())
            }
        }
        assertEquals(4L, h.droppedCount)
        h.start()
        assertTrue(all.await(10, TimeUnit.SECONDS), "sent ${got.size} of 16")
        h.stop()
        assertTrue(h.awaitStopped(10_000))
        assertEquals(offered.take(16), got.map { it.first })
        assertEquals((0 until 16).map { 1_000L + it }, got.map { it.second })
        assertEquals(4L, h.droppedCount)
    }

    @Test
    fun `stop wakes the sender waiting for a message`() {
        val sent = CountDownLatch(1)
        val h = HandOff(16, "test-sender") { _, _ -> sent.countDown() }
        h.start()
        h.orientation(1, 1.0, 0.0, 0.0, 0.0)
        assertTrue(sent.await(10, TimeUnit.SECONDS))
        // The sender now waits on an empty queue: stop must end it, not leave it waiting for a message that never comes.
        h.stop()
        assertTrue(h.awaitStopped(10_000), "the sender still waits")
    }
}
