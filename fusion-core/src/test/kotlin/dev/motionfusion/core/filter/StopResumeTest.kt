package dev.motionfusion.core.filter

import dev.motionfusion.core.STANDARD_GRAVITY
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.sim.MagneticDisturbance
import dev.motionfusion.core.sim.MagneticDisturbanceKind
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import dev.motionfusion.core.sim.ViolentMotion
import dev.motionfusion.core.sim.ViolentMotionKind
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.TestFactory

/**
 * state()/restore() carry every unit's state: a replay stopped at a point where each mechanism holds
 * state of its own (the rest bias being learnt, the accelerometer low-pass and heading convergence just
 * after the start, the inclination recovery after a shake, a magnetic disturbance being held, the
 * heading gain ramping back after it) and resumed in a new filter continues bit for bit: every later
 * orientation and the final state equal the unbroken run's. Leaving any stage's state out of FilterState
 * makes one of these fail. reset() returns a used filter to a new one's state.
 */
class StopResumeTest {
    private val data: List<SimulatedSample> = MotionSimulator(
        SimulationSettings(
            seed = 5L, rateHz = 200.0, durationS = 45.0, angularRate = 1.0, gyroBias = Vector3(0.01, -0.008, 0.005),
            restWindows = listOf(TimeWindow(0.0, 4.0), TimeWindow(8.0 + ViolentMotionKind.SHAKE.durationS, 13.0)),
            violentMotions = listOf(ViolentMotion(ViolentMotionKind.SHAKE, 8.0)),
            magDisturbances = listOf(MagneticDisturbance(MagneticDisturbanceKind.WEAK_TILTED_HALL, 20.0, 8.0)),
            accRange = 8.0 * STANDARD_GRAVITY, gyroScaleError = 0.05,
        ),
    ).run()

    private val phone = FilterSettings(
        magDisturbanceRejection = true, magNormTolerance = 0.3, magDipTolerance = 0.35,
        magNewFieldTime = 20.0, magNewFieldMinGyro = 0.35, magResumeTime = 3.0, accRejection = true,
    )

    private fun step(f: MadgwickFilter, s: SimulatedSample) = f.update(s.timestampNs, s.gyro, s.acc, s.mag)

    /** Orientations [w, x, y, z] of every step from [from] on. */
    private fun trace(f: MadgwickFilter, from: Int): DoubleArray {
        val out = DoubleArray(4 * (data.size - from))
        for (i in from until data.size) {
            step(f, data[i])
            f.orientationInto(out, 4 * (i - from))
        }
        return out
    }

    /**
     * The number of steps after which to stop: the middle of the first run of at least 10 steps, from
     * [fromS] s on, after each of which [holds] is true of the unbroken run's filter.
     */
    private fun middle(settings: FilterSettings, fromS: Double, holds: (MadgwickFilter) -> Boolean): Int {
        val f = MadgwickFilter(settings)
        val from = data.indexOfFirst { it.timestampNs >= (fromS * 1e9).toLong() }
        var start = -1
        for (i in data.indices) {
            step(f, data[i])
            if (i < from) continue
            if (holds(f)) {
                if (start < 0) start = i
            } else {
                if (start >= 0 && i - start >= 10) return (start + i) / 2 + 1
                start = -1
            }
        }
        error("no run of 10 steps from $fromS s on where the state looked for holds")
    }

    private fun stopAndResume(settings: FilterSettings, split: Int, what: String) {
        val whole = MadgwickFilter(settings)
        val expected = trace(whole, 0).copyOfRange(4 * split, 4 * data.size)
        val first = MadgwickFilter(settings)
        for (i in 0 until split) step(first, data[i])
        val second = MadgwickFilter(settings)
        second.restore(first.state())
        assertEquals(first.state(), second.state(), what)
        assertArrayEquals(expected, trace(second, split), "$what: the continuation differs")
        assertEquals(whole.state(), second.state(), what)
        assertEquals(whole.diagnostics(), second.diagnostics(), what)
    }

    private fun case(name: String, settings: FilterSettings, split: () -> Int) = DynamicTest.dynamicTest(name) {
        stopAndResume(settings, split(), name)
    }

    @TestFactory
    fun `a replay stopped and resumed where each unit holds state continues bit for bit`() = listOf(
        case("just after the start (low-pass averaging, heading converging)", phone) { 40 },
        case("at rest, the bias being learnt", phone) { middle(phone, 0.0) { it.diagnostics().atRest } },
        case("during the inclination recovery after the shake", phone) { middle(phone, 8.0) { it.inclinationRecovering } },
        case("during a magnetic disturbance hold", phone) { middle(phone, 0.0) { it.diagnostics().magneticDisturbance } },
        case("during the heading gain's ramp after the disturbance", phone) {
            middle(phone, 0.0) { it.magneticGainFactor > 0.0 && it.magneticGainFactor < 1.0 }
        },
        budget.let { s ->
            case("with the hold's budget spent, the disturbed field used at half the gain", s) {
                middle(s, 0.0) { it.diagnostics().magneticDisturbance && it.magneticGainFactor == 0.5 }
            }
        },
        trusting.let { s ->
            case("while the field wanders and the magnetic trust weighs the heading gain down", s) {
                middle(s, 0.0) { it.magneticTrust > 0.1 && it.magneticTrust < 0.9 }
            }
        },
        margZeta.let { s -> case("the report's MARG gradient with ζ, the accelerometer rejected", s) { middle(s, 0.0) { it.diagnostics().accelerometerRejected } } },
    )

    private val budget = phone.copy(magRejectionFactor = 2.0, magMaxRejectionTime = 3.0, magFirstFieldTime = 2.0, magUndisturbedTime = 0.5)

    private val trusting = FilterSettings(magTrustSpread = 0.01)

    private val margZeta = FilterSettings(headingGain = null, zeta = 0.002, accRejection = true)

    @Test
    fun `the bias is being learnt where the run stops at rest`() {
        val split = middle(phone, 0.0) { it.diagnostics().atRest }
        val f = MadgwickFilter(phone)
        for (i in 0 until split) step(f, data[i])
        val before = f.diagnostics().gyroBias
        step(f, data[split])
        assertNotEquals(before, f.diagnostics().gyroBias)
    }

    @Test
    fun `reset returns a used filter to a new one`() {
        val used = MadgwickFilter(phone)
        for (i in 0 until data.size / 2) step(used, data[i])
        assertNotEquals(MadgwickFilter(phone).state(), used.state())
        used.reset()
        assertEquals(MadgwickFilter(phone).state(), used.state())
        assertArrayEquals(trace(MadgwickFilter(phone), 0), trace(used, 0))
    }
}
