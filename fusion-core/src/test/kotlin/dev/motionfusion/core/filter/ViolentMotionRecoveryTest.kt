package dev.motionfusion.core.filter

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.filter.SimulatedRuns.assertSplitRunEqualsWhole
import dev.motionfusion.core.filter.SimulatedRuns.inclinationDeg
import dev.motionfusion.core.filter.SimulatedRuns.index
import dev.motionfusion.core.filter.SimulatedRuns.max
import dev.motionfusion.core.filter.SimulatedRuns.run
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import dev.motionfusion.core.sim.ViolentMotion
import dev.motionfusion.core.sim.ViolentMotionKind
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.TestFactory

/**
 * Recovery after any large error (recoveryAngle): each simulated violent motion (a drop onto a
 * table, a person falling, a shake, a throw and catch) on a phone whose accelerometer clips at ±8 g
 * and whose gyroscope reads 3 % high (uncalibrated phones are off by up to a few per cent), none reaching the gyroscope's range, followed by the phone
 * lying still. 1.5 s after it comes to rest the inclination is within 1° of the truth, and stays so;
 * with the mechanism off it is not.
 */
class ViolentMotionRecoveryTest {
    private fun data(kind: ViolentMotionKind) = MotionSimulator(
        SimulationSettings(
            seed = 21L, rateHz = 200.0, durationS = 20.0, angularRate = 0.6,
            restWindows = listOf(TimeWindow(0.0, 4.0), TimeWindow(6.0 + kind.durationS, 20.0)),
            violentMotions = listOf(ViolentMotion(kind, 6.0)),
            accRange = 8.0 * STANDARD_GRAVITY, gyroScaleError = 0.03,
        ),
    ).run()

    /** The largest inclination error from 1.5 s to 6 s after the phone comes to rest, °. */
    private fun worstAfterRest(kind: ViolentMotionKind, settings: FilterSettings): Double {
        val d = data(kind)
        val rest = 6.0 + kind.durationS
        return max(run(MadgwickFilter(settings), d), d, index(d, rest + 1.5), index(d, rest + 6.0), ::inclinationDeg)
    }

    @TestFactory
    fun `inclination comes back within 1 degree 1·5 s after each violent motion`() = ViolentMotionKind.entries.map { kind ->
        DynamicTest.dynamicTest(kind.name) {
            val on = worstAfterRest(kind, FilterSettings())
            val off = worstAfterRest(kind, FilterSettings(recoveryAngle = null))
            println("$kind: with recovery $on°, without $off°")
            assertTrue(on < 1.0, "$kind: inclination $on° off 1.5–6 s after rest with the recovery")
            assertTrue(off > 1.0, "$kind: without the recovery it should stay off (got $off°): the test would not show the mechanism")
        }
    }

    @TestFactory
    fun `a run stopped and restored while still or recovering continues bit for bit`() = listOf(0.1, 0.25, 0.6, 1.0).map { after ->
        DynamicTest.dynamicTest("${after} s after the shake") {
            val d = data(ViolentMotionKind.SHAKE)
            assertSplitRunEqualsWhole(FilterSettings(), d, index(d, 6.0 + ViolentMotionKind.SHAKE.durationS + after))
        }
    }
}
