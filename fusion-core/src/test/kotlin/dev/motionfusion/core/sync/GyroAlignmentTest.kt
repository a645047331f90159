package dev.motionfusion.core.sync

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import dev.motionfusion.core.sim.ViolentMotion
import dev.motionfusion.core.sim.ViolentMotionKind
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import kotlin.math.abs

/** Two simulated phones shaken together, their clocks apart by a known offset (issue 39: within one sample period). */
class GyroAlignmentTest {
    /** One phone's |ω| over [seconds] at [rateHz], its clock [clockNs] ahead of the true time; shaken at 20 s and dropped at 41 s. */
    private fun phone(rateHz: Double, clockNs: Long, seed: Long, seconds: Double = 60.0, violent: Boolean = true, orientation: Quaternion = Quaternion.IDENTITY): Pair<LongArray, DoubleArray> {
        val settings = SimulationSettings(
            seed = seed, rateHz = rateHz, durationS = seconds, initialOrientation = orientation,
            restWindows = if (violent) listOf(TimeWindow(0.0, seconds)) else emptyList(),
            violentMotions = if (violent) listOf(ViolentMotion(ViolentMotionKind.SHAKE, 20.0), ViolentMotion(ViolentMotionKind.DROP, 41.0)) else emptyList(),
            gyroNoise = 0.01,
        )
        val samples = MotionSimulator(settings).run()
        return LongArray(samples.size) { samples[it].timestampNs + clockNs } to DoubleArray(samples.size) { samples[it].gyro.norm() }
    }

    @Test
    fun `a shake recovers the offset between two phones within one sample period`() {
        for ((clockB, rateB) in listOf(3_217_345_678L to 100.0, -47_000_001_234L to 200.0, 5_000_000L to 50.0)) {
            val (at, ar) = phone(200.0, 0, seed = 11)
            val (bt, br) = phone(rateB, clockB, seed = 12, orientation = Quaternion.fromAxisAngle(Vector3(0.0, 1.0, 0.0), 2.0))
            val r = GyroAlignment.align(at, ar, bt, br)
            val period = (1e9 / rateB).toLong()
            println("B ahead by ${clockB / 1e6} ms at $rateB Hz: found ${-r.offsetNs / 1e6} ms (error ${(r.offsetNs + clockB) / 1e6} ms), r ${"%.3f".format(r.correlation)}, runner-up ${"%.3f".format(r.runnerUp)}")
            assertTrue(abs(r.offsetNs + clockB) <= period, "error ${(r.offsetNs + clockB) / 1e6} ms at $rateB Hz")
            // The shake's 4 Hz repeats within it; its start and end, and the drop, single the peak out.
            assertTrue(r.correlation > 0.95 && r.correlation - r.runnerUp > 0.15, "peak ${r.correlation}, runner-up ${r.runnerUp}")
        }
    }

    @Test
    fun `an expected offset narrows the search`() {
        val (at, ar) = phone(200.0, 0, seed = 11)
        val (bt, br) = phone(100.0, 90_000_000_000L, seed = 12)
        // 90 s is beyond the default ±60 s around 0: no overlap of 5 s there is refused...
        assertThrows<IllegalArgumentException> { GyroAlignment.align(at, ar, bt, br, maxLagNs = 10_000_000_000) }
        // ...and found around a UTC-based guess 2 s off.
        val r = GyroAlignment.align(at, ar, bt, br, maxLagNs = 5_000_000_000, expectedNs = -88_000_000_000)
        assertEquals(-90_000_000_000.0, r.offsetNs.toDouble(), 10_000_000.0)
    }

    @Test
    fun `a motion that repeats is reported as ambiguous`() {
        // Turning back and forth every 2 s and nothing else: every 2 s of lag fits as well.
        fun swing(clockNs: Long) = LongArray(6000) { it * 10_000_000L + clockNs } to DoubleArray(6000) { 1 + kotlin.math.sin(2 * Math.PI * 0.5 * it / 100.0) }
        val (at, ar) = swing(0)
        val (bt, br) = swing(700_000_000)
        val r = GyroAlignment.align(at, ar, bt, br)
        assertTrue(r.correlation - r.runnerUp < 0.01, "runner-up ${r.runnerUp} beside ${r.correlation}")
    }

    @Test
    fun `bad input is refused with its reason`() {
        val t = longArrayOf(0, 10, 20, 30)
        val v = doubleArrayOf(0.0, 1.0, 0.0, 1.0)
        assertThrows<IllegalArgumentException> { GyroAlignment.align(t, v, longArrayOf(0, 10), doubleArrayOf(0.0, 1.0)) }
        assertThrows<IllegalArgumentException> { GyroAlignment.align(t, v, longArrayOf(0, 10, 10), doubleArrayOf(0.0, 1.0, 2.0)) }
        assertThrows<IllegalArgumentException> { GyroAlignment.align(t, v, t, doubleArrayOf(0.0, Double.NaN, 0.0, 1.0)) }
        assertThrows<IllegalArgumentException> { GyroAlignment.align(t, v, t, doubleArrayOf(0.0, 1.0)) }
    }
}
