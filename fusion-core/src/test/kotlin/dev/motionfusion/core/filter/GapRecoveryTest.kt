package dev.motionfusion.core.filter

import dev.motionfusion.core.filter.SimulatedRuns.assertSplitRunEqualsWhole
import dev.motionfusion.core.filter.SimulatedRuns.index
import dev.motionfusion.core.filter.SimulatedRuns.max
import dev.motionfusion.core.filter.SimulatedRuns.run
import dev.motionfusion.core.filter.SimulatedRuns.totalDeg
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.TestFactory

/**
 * A gap longer than maxGap in the middle of a recording (every sensor silent for 3 s while the phone
 * turns on, as in an export whose app was paused): nothing is integrated over it, so the estimate is as
 * far off as the phone turned. The filter recovers as after a saturated reading, and a few seconds
 * later it is back on the truth; with the two recoveries off it stays where the gap left it.
 */
class GapRecoveryTest {
    private val gapFrom = 12.0
    private val gapTo = 15.0

    private val data: List<SimulatedSample> = MotionSimulator(
        SimulationSettings(seed = 8L, rateHz = 200.0, durationS = 30.0, angularRate = 0.6, restWindows = listOf(TimeWindow(0.0, 4.0))),
    ).run().filter { it.timestampNs < gapFrom * 1e9 || it.timestampNs >= gapTo * 1e9 }

    /** The largest total error from [fromS] to [toS] after the gap, °. */
    private fun worst(settings: FilterSettings, fromS: Double, toS: Double): Double =
        max(run(MadgwickFilter(settings), data), data, index(data, gapTo + fromS), index(data, gapTo + toS), ::totalDeg)

    @Test
    fun `the estimate comes back after a gap, and stays off without the recoveries`() {
        val before = max(run(MadgwickFilter(FilterSettings()), data), data, index(data, gapFrom - 4.0), index(data, gapFrom - 0.1), ::totalDeg)
        val justAfter = worst(FilterSettings(), 0.0, 0.2)
        val on = worst(FilterSettings(), 4.0, 14.0)
        val off = worst(FilterSettings(inclinationRecoveryBeta = null, headingRecoveryTime = null), 4.0, 14.0)
        println("gap: before $before°, just after $justAfter°, 4–14 s after: $on° (recoveries off: $off°)")
        assertTrue(justAfter > 10.0, "the gap should leave the estimate far off (got $justAfter°): the test would not show the recovery")
        assertTrue(on < 2.0 * maxOf(before, 1.0), "4–14 s after the gap the error is $on° (before it $before°)")
        assertTrue(off > 10.0, "without the recoveries the estimate should stay off (got $off°)")
        val d = MadgwickFilter(FilterSettings()).also { f -> data.forEach { f.update(it.timestampNs, it.gyro, it.acc, it.mag) } }.diagnostics()
        assertEquals(1L, d.skippedGap, "the one sample after the gap is not integrated")
    }

    @TestFactory
    fun `a run stopped at the gap continues bit for bit`() = listOf(0, 1, 2).map { afterGap ->
        DynamicTest.dynamicTest("$afterGap samples after the gap") {
            assertSplitRunEqualsWhole(FilterSettings(), data, index(data, gapTo) + afterGap)
        }
    }
}
