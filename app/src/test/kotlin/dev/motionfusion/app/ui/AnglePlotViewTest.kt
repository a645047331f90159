package dev.motionfusion.app.ui

import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment

/** The live plot keeps 10 s of sample time whatever the rate its points arrive at. */
@RunWith(RobolectricTestRunner::class)
class AnglePlotViewTest {
    private fun feed(rateHz: Int, seconds: Int): AnglePlotView {
        val plot = AnglePlotView(RuntimeEnvironment.getApplication())
        val stepNs = 1_000_000_000L / rateHz
        var t = 5_000_000_000L
        repeat(rateHz * seconds) { i ->
            plot.append(t, (i % 360).toDouble(), 10.0, -20.0)
            t += stepNs
        }
        return plot
    }

    @Test
    fun `frames at 60 and 120 Hz both span 10 seconds`() {
        for (rate in listOf(60, 120, 240)) {
            val plot = feed(rate, 30)
            val frame = 1.0 / rate
            // The window plus the one point before it that carries the line to the left edge.
            assertEquals("span at $rate Hz", 10.0, plot.spanSeconds, 1.5 * frame)
            assertTrue("span at $rate Hz reaches the window: ${plot.spanSeconds}", plot.spanSeconds >= 10.0)
            assertEquals("points at $rate Hz", 10.0 * rate + 1, plot.pointCount.toDouble(), 1.0)
        }
    }

    @Test
    fun `a gap longer than the window leaves the newest point and the one before`() {
        val plot = feed(60, 5)
        plot.append(100_000_000_000L, 1.0, 2.0, 3.0)
        assertEquals(2, plot.pointCount)
    }

    @Test
    fun `a whole series spans its samples`() {
        val plot = AnglePlotView(RuntimeEnvironment.getApplication())
        val n = 3000
        plot.showSeries(7_000_000_000L, FloatArray(n) { it * 0.01f }, FloatArray(n), FloatArray(n), FloatArray(n), emptyList())
        assertEquals(n, plot.pointCount)
        assertEquals(29.99, plot.spanSeconds, 1e-3)
    }

    @Test
    fun `the three series have distinct colours`() {
        val plot = AnglePlotView(RuntimeEnvironment.getApplication())
        assertEquals(3, setOf(plot.colour(0), plot.colour(1), plot.colour(2)).size)
    }
}
