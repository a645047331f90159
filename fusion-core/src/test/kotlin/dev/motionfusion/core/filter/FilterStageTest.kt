package dev.motionfusion.core.filter

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.sqrt

/**
 * A disturbance detector added to the filter takes one class (the toy [FieldBand] below, a file of its own
 * in main code) and one line in the composition (MadgwickFilter's `checks`; here [MadgwickFilter.withChecks]):
 * its decision enters the step, its state enters FilterState (stop and resume stay bit for bit) and reset.
 */
class FilterStageTest {
    /** The toy: a magnetometer reading whose magnitude is outside [low, high] µT is left out; counts them. */
    private class FieldBand(private val low: Double, private val high: Double) : Check<FieldBand.State> {
        private var rejected = 0L
        private var lastNorm = 0.0

        override fun check(s: Step) {
            if (!s.useMag) return
            lastNorm = sqrt(s.mx * s.mx + s.my * s.my + s.mz * s.mz)
            if (lastNorm < low || lastNorm > high) {
                rejected++
                s.useMag = false
            }
        }

        data class State(val rejected: Long, val lastNorm: Double)

        override fun state() = State(rejected, lastNorm)

        override fun restore(state: State) {
            rejected = state.rejected
            lastNorm = state.lastNorm
        }

        override fun reset() = restore(State(0L, 0.0))
    }

    // A hard iron from 8 to 16 s lifts the field's magnitude from 48 µT to about 100 µT.
    private val data: List<SimulatedSample> = MotionSimulator(
        SimulationSettings(seed = 7L, durationS = 24.0, hardIron = Vector3(40.0, 30.0, -20.0), hardIronWindow = TimeWindow(8.0, 16.0)),
    ).run()

    private val settings = FilterSettings(initialisation = Initialisation.IDENTITY)

    private fun trace(f: MadgwickFilter, from: Int = 0, useMag: Boolean = true): DoubleArray {
        val out = DoubleArray(4 * (data.size - from))
        for (i in from until data.size) {
            val s = data[i]
            if (useMag) f.update(s.timestampNs, s.gyro, s.acc, s.mag) else f.update(s.timestampNs, s.gyro, s.acc)
            f.orientationInto(out, 4 * (i - from))
        }
        return out
    }

    @Test
    fun `a check that leaves out every magnetometer reading makes the MARG filter run as on data without one`() {
        val band = FieldBand(0.0, 0.0)
        val rejecting = MadgwickFilter(settings).withChecks(band)
        assertArrayEquals(trace(MadgwickFilter(settings), useMag = false), trace(rejecting))
        assertEquals(rejecting.diagnostics().gyroscopeSteps, band.state().rejected)
    }

    @Test
    fun `the check's decision changes the estimate only where it rejects`() {
        val band = FieldBand(30.0, 70.0)
        val withBand = trace(MadgwickFilter(settings).withChecks(band))
        val plain = trace(MadgwickFilter(settings))
        val firstRejected = data.indexOfFirst { it.timestampNs >= 8_000_000_000L }
        assertArrayEquals(plain.copyOfRange(0, 4 * firstRejected), withBand.copyOfRange(0, 4 * firstRejected))
        assertNotEquals(plain[4 * (firstRejected + 200)], withBand[4 * (firstRejected + 200)])
        assertTrue(band.state().rejected > 1000, "rejected ${band.state().rejected}")
    }

    @Test
    fun `the check's state is in FilterState, so a run stopped inside the disturbance resumes bit for bit`() {
        val split = data.indexOfFirst { it.timestampNs >= 12_000_000_000L }
        val whole = MadgwickFilter(settings).withChecks(FieldBand(30.0, 70.0))
        val expected = trace(whole).copyOfRange(4 * split, 4 * data.size)
        val first = MadgwickFilter(settings).withChecks(FieldBand(30.0, 70.0))
        for (i in 0 until split) data[i].let { first.update(it.timestampNs, it.gyro, it.acc, it.mag) }
        val stopped = first.state()
        assertTrue((stopped.checks.last() as FieldBand.State).rejected > 0)
        val second = MadgwickFilter(settings).withChecks(FieldBand(30.0, 70.0))
        second.restore(stopped)
        assertEquals(stopped, second.state())
        assertArrayEquals(expected, trace(second, split))
        assertEquals(whole.state(), second.state())
    }

    @Test
    fun `reset returns the check to its new state`() {
        val f = MadgwickFilter(settings).withChecks(FieldBand(30.0, 70.0))
        trace(f)
        assertNotEquals(MadgwickFilter(settings).withChecks(FieldBand(30.0, 70.0)).state(), f.state())
        f.reset()
        assertEquals(MadgwickFilter(settings).withChecks(FieldBand(30.0, 70.0)).state(), f.state())
    }
}
