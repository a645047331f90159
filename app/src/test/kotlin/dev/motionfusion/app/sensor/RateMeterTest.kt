package dev.motionfusion.app.sensor

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/** Rate and jitter from timestamps, on the JVM. */
class RateMeterTest {
    @Test
    fun `steady 100 Hz gives 100 Hz and no jitter`() {
        val m = RateMeter()
        for (i in 0..500) m.add(1_000_000_000L + i * 10_000_000L)
        assertEquals(100.0, m.rateHz(), 1e-9)
        assertEquals(0.0, m.jitterMs(), 1e-9)
        assertEquals(501, m.samples)
    }

    @Test
    fun `alternating 9 and 11 ms intervals give 100 Hz and 1 ms jitter`() {
        val m = RateMeter(window = 100)
        var t = 0L
        m.add(t)
        for (i in 0 until 100) {
            t += if (i % 2 == 0) 9_000_000L else 11_000_000L
            m.add(t)
        }
        assertEquals(100.0, m.rateHz(), 1e-9)
        // Sample standard deviation of 100 values ±1 ms: sqrt(100/99).
        assertEquals(Math.sqrt(100.0 / 99.0), m.jitterMs(), 1e-9)
    }

    @Test
    fun `duplicate and backward timestamps are counted and left out`() {
        val m = RateMeter()
        m.add(0); m.add(5_000_000); m.add(5_000_000); m.add(10_000_000); m.add(2_000_000); m.add(7_000_000)
        assertEquals(1, m.duplicates)
        assertEquals(1, m.backwards)
        // Intervals kept: 5, 5, 5 ms.
        assertEquals(200.0, m.rateHz(), 1e-9)
    }

    @Test
    fun `the window follows a change of rate`() {
        val m = RateMeter(window = 50)
        var t = 0L
        repeat(200) { t += 20_000_000L; m.add(t) }
        assertEquals(50.0, m.rateHz(), 1e-9)
        repeat(50) { t += 5_000_000L; m.add(t) }
        assertEquals(200.0, m.rateHz(), 1e-9)
    }

    @Test
    fun `no rate before two samples, no jitter before three`() {
        val m = RateMeter()
        assertTrue(m.rateHz().isNaN())
        m.add(1)
        assertTrue(m.rateHz().isNaN())
        m.add(10_000_001)
        assertEquals(100.0, m.rateHz(), 1e-9)
        assertTrue(m.jitterMs().isNaN())
    }

    @Test
    fun `sampling rates round-trip through their keys and reject nonsense`() {
        for (r in SamplingRate.Delay.entries + listOf(SamplingRate.Hz(1), SamplingRate.Hz(100), SamplingRate.Hz(1000))) {
            assertEquals(r, SamplingRate.parse(r.key))
        }
        assertEquals(10_000, SamplingRate.Hz(100).registerArgument)
        assertEquals(1, SamplingRate.Delay.GAME.registerArgument) // SENSOR_DELAY_GAME, not 1 µs
        for (bad in listOf("", "hz:", "hz:0", "hz:1001", "hz:x", "slow")) assertNull(SamplingRate.parse(bad), bad)
        assertThrows(IllegalArgumentException::class.java) { SamplingRate.Hz(0) }
    }
}
