package dev.motionfusion.app.record

import dev.motionfusion.app.settings.RecordingLimits
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Test

/** A recording's limits on their own, on a clock the test sets (no service, no sleeping). */
class RecordingLimitWatchTest {
    private var battery = BatteryState(50, charging = false)
    private var reads = 0
    private val source = BatterySource { reads++; battery }
    private val s = 1_000_000_000L

    @Test
    fun `the maximum duration ends the recording at its second, counted from the recording's start`() {
        // Started at 100 s of elapsed realtime (a resumed recording keeps its first start).
        val w = RecordingLimitWatch(RecordingLimits(maxDurationS = 60, stopBatteryPercent = 0), startedElapsedMs = 100_000, battery = source)
        assertNull(w.reached(159 * s))
        assertNull(w.reached(160 * s - 1))
        assertEquals(RecordingEnd.MaxDuration(60), w.reached(160 * s))
        assertEquals(0, reads, "no battery limit: the battery is never read")
    }

    @Test
    fun `the battery is read every 30 s, and ends the recording at or below its level only while not charging`() {
        val w = RecordingLimitWatch(RecordingLimits(maxDurationS = 0, stopBatteryPercent = 15), startedElapsedMs = 0, battery = source)
        assertNull(w.reached(1 * s))
        assertEquals(1, reads)
        battery = BatteryState(10, charging = false)
        // Read again only 30 s after the last read: a second later nothing is read, so nothing is seen.
        assertNull(w.reached(2 * s))
        assertNull(w.reached(31 * s - 1))
        assertEquals(1, reads)
        battery = BatteryState(10, charging = true)
        assertNull(w.reached(31 * s), "charging: no stop")
        assertEquals(2, reads)
        battery = BatteryState(15, charging = false)
        assertEquals(RecordingEnd.BatteryLow(15), w.reached(61 * s))
        assertEquals(3, reads)
    }
}
