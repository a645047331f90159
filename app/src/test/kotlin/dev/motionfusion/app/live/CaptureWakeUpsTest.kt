package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.EventRing
import dev.motionfusion.core.event.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import dev.motionfusion.app.fusion.Capture

/**
 * The capture thread sleeps until there is work: after a batch it waits the interval that lets the
 * next events gather (10 ms with a screen showing them, 100 ms recording with nothing on screen),
 * with nothing queued until the sensor thread offers an event (no 2-ms polling), at most until the
 * reorder window must be emptied; and the ring wakes a waiting consumer when an event comes.
 */
class CaptureWakeUpsTest {
    @Test
    fun `the wait after a batch follows what the capture has to do`() {
        val quiet = 100_000_000L
        assertEquals(0L, Capture.waitAfter(4096, 10, recording = true, onScreen = true))
        assertEquals(Capture.ON_SCREEN_WAIT_NS, Capture.waitAfter(12, 3, recording = false, onScreen = true))
        assertEquals(Capture.OFF_SCREEN_WAIT_NS, Capture.waitAfter(12, 3, recording = true, onScreen = false))
        assertEquals(quiet, Capture.waitAfter(0, 3, recording = true, onScreen = true, quietFlushNs = quiet))
        assertEquals(Capture.IDLE_WAIT_NS, Capture.waitAfter(0, 0, recording = false, onScreen = true))
        // Nothing is polled: every wait is 10 ms or more (the thread woke every 2 ms before).
        for (drained in listOf(1, 100)) for (screen in listOf(true, false)) assertTrue(Capture.waitAfter(drained, 0, true, screen) >= 10_000_000L)
        // At most 100 wake-ups a second on screen, 10 with the screen off, while events flow.
        assertEquals(100L, 1_000_000_000L / Capture.ON_SCREEN_WAIT_NS)
        assertEquals(10L, 1_000_000_000L / Capture.OFF_SCREEN_WAIT_NS)
    }

    @Test
    fun `a consumer waiting on an empty ring is woken by the next event`() {
        val ring = EventRing(16)
        var returned = false
        val consumer = Thread {
            ring.awaitEvent(60_000_000_000L) // a minute: only the offer can end it in time
            returned = true
        }
        consumer.start()
        // Once the consumer is parked on the empty ring, the offer alone can wake it.
        while (consumer.state != Thread.State.TIMED_WAITING) Thread.onSpinWait()
        ring.offer(SessionStream.GYROSCOPE, 1L, 3, floatArrayOf(0f, 0f, 0f), 3)
        consumer.join(10_000)
        assertFalse(consumer.isAlive, "the consumer still waits")
        assertTrue(returned)
        assertEquals(1, ring.size)
    }
}
