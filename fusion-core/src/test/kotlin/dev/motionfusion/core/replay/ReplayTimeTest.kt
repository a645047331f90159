package dev.motionfusion.core.replay

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test

class ReplayTimeTest {
    @Test
    fun `seconds between two timestamps never wrap round`() {
        assertEquals(1.5, Replayer.secondsBetween(1_000_000_000_000L, 1_001_500_000_000L), 0.0)
        assertEquals(-2e-9, Replayer.secondsBetween(5L, 3L), 0.0)
        // Opposite signs far apart: a Long difference would wrap to a negative (or positive) time.
        assertEquals(2.0 * Long.MAX_VALUE * 1e-9, Replayer.secondsBetween(-Long.MAX_VALUE, Long.MAX_VALUE), 1e-3 * Long.MAX_VALUE * 1e-9)
        assertEquals(-(Long.MAX_VALUE.toDouble() - Long.MIN_VALUE.toDouble()) * 1e-9, Replayer.secondsBetween(Long.MAX_VALUE, Long.MIN_VALUE), 1.0)
        assertEquals(Long.MAX_VALUE * 1e-9, Replayer.secondsBetween(0L, Long.MAX_VALUE), 0.0)
    }
}
