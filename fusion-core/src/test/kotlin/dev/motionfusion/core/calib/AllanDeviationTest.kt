package dev.motionfusion.core.calib

import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.abs
import kotlin.math.sqrt
import kotlin.random.Random

class AllanDeviationTest {

    /** The textbook overlapping Allan deviation, computed directly from all samples in memory. */
    private fun reference(y: DoubleArray, m: Int): Double {
        val x = DoubleArray(y.size + 1)
        for (i in y.indices) x[i + 1] = x[i] + y[i]
        var s = 0.0
        val n = x.size - 2 * m
        for (k in 0 until n) { val d = x[k + 2 * m] - 2 * x[k + m] + x[k]; s += d * d }
        return sqrt(s / (2.0 * m * m * n))
    }

    @Test
    fun `the streaming estimate matches the direct overlapping Allan deviation`() {
        val r = Random(11)
        val n = 60_000
        val y = DoubleArray(n)
        var walk = 0.0
        for (i in y.indices) { walk += 0.001 * r.nextDouble(-1.0, 1.0); y[i] = 0.3 + r.nextDouble(-1.0, 1.0) + walk }
        val acc = AllanAccumulator()
        for (i in y.indices) acc.add(i * 10_000_000L, y[i], 2 * y[i], -y[i])
        val c = acc.curve()
        assertEquals(100.0, c.rateHz, 1e-9)
        assertTrue(c.tau.size > 30)
        for ((i, tau) in c.tau.withIndex()) {
            val m = Math.round(tau * 100.0).toInt()
            val ref = reference(y, m)
            val rel = abs(c.deviation[0][i] - ref) / ref
            // Every k below 512 samples; at a stride of at most 1/256 of the cluster above.
            assertTrue(rel < (if (m < 512) 1e-9 else 0.02), "m=$m: ${c.deviation[0][i]} vs $ref")
            assertEquals(2 * c.deviation[0][i], c.deviation[1][i], 1e-9 * c.deviation[1][i])
        }
        assertTrue(c.tau.last() <= n / 100.0 / 3.0)
    }

    @Test
    fun `white noise and random walk densities of a simulated still recording are recovered within 10 percent`() {
        // Random walk and white noise cross at τ = √3·N/K ≈ 2 s; four hours put many clusters on both lines.
        val gyroN = 0.002
        val gyroK = 0.0017
        val accN = 0.02
        val accK = 0.017
        val hours = 4.0
        val s = SimulationSettings(
            rateHz = 50.0, durationS = 3600.0 * hours, angularRate = 0.0, restWindows = listOf(TimeWindow(0.0, 1e9)),
            gyroNoise = 0.0, accNoise = 0.0, magNoise = 0.0,
            gyroNoiseDensity = gyroN, gyroBiasDrift = gyroK, accNoiseDensity = accN, accBiasDrift = accK,
        )
        val gyro = AllanAccumulator()
        val acc = AllanAccumulator()
        MotionSimulator(s).forEach {
            gyro.add(it.timestampNs, it.gyro.x, it.gyro.y, it.gyro.z)
            acc.add(it.timestampNs, it.acc.x, it.acc.y, it.acc.z)
        }
        for ((name, curve, n, k) in listOf(Quad("gyroscope", gyro.curve(), gyroN, gyroK), Quad("accelerometer", acc.curve(), accN, accK))) {
            for ((axis, t) in curve.fits().withIndex()) {
                val en = t.whiteNoise / n - 1
                val ek = t.randomWalk / k - 1
                println("%s axis %d: N %.4g (%+.1f %%), K %.4g (%+.1f %%), B %.3g at %.0f s".format(name, axis, t.whiteNoise, 100 * en, t.randomWalk, 100 * ek, t.biasInstability, t.biasInstabilityTau))
                assertTrue(abs(en) < 0.10, "$name axis $axis: N ${t.whiteNoise} vs $n")
                assertTrue(abs(ek) < 0.10, "$name axis $axis: K ${t.randomWalk} vs $k")
            }
        }
    }

    @Test
    fun `a short recording of white noise has no random walk and reports an upper bound`() {
        val r = Random(2)
        val acc = AllanAccumulator()
        for (i in 0 until 30_000) acc.add(i * 5_000_000L, 0.01 * r.nextDouble(-1.0, 1.0), 0.0, 0.0)
        val t = acc.curve().fits()[0]
        // Uniform on ±0.01 at 200 Hz: σ = 0.01/√3, density σ/√200.
        assertEquals(0.01 / sqrt(3.0) / sqrt(200.0), t.whiteNoise, 0.05 * t.whiteNoise)
        assertTrue(t.randomWalk.isNaN())
        assertTrue(t.randomWalkUpperBound > 0.0)
    }

    private data class Quad(val name: String, val curve: AllanCurve, val n: Double, val k: Double)
}
