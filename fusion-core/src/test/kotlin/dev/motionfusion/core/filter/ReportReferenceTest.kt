package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.eval.Trial
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulatedSample
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.Test
import java.io.File
import kotlin.math.abs
import kotlin.math.roundToLong
import kotlin.math.sqrt

/**
 * The filter with the report's settings against a straightforward, independent transcription of
 * the report's equations: explicit 6×4 Jacobian, ∇f = Jᵀf by loops, quaternion products through
 * a generic Hamilton product. Both in double precision; they must agree to float precision.
 */
class ReportReferenceTest {
    /** The report's filter written from the equations, matrices and all. */
    private class Reference(val beta: Double, val zeta: Double, val marg: Boolean) {
        var q = doubleArrayOf(1.0, 0.0, 0.0, 0.0)
        var bias = doubleArrayOf(0.0, 0.0, 0.0)
        var b = doubleArrayOf(0.0, 1.0, 0.0, 0.0)

        fun step(dt: Double, gyro: Vector3, acc: Vector3, mag: Vector3) {
            val a = unit(acc)
            val (q1, q2, q3, q4) = q.toList()
            val fg = doubleArrayOf( // (eq. 25)
                2 * (q2 * q4 - q1 * q3) - a[0],
                2 * (q1 * q2 + q3 * q4) - a[1],
                2 * (0.5 - q2 * q2 - q3 * q3) - a[2],
            )
            val jg = arrayOf( // (eq. 26)
                doubleArrayOf(-2 * q3, 2 * q4, -2 * q1, 2 * q2),
                doubleArrayOf(2 * q2, 2 * q1, 2 * q4, 2 * q3),
                doubleArrayOf(0.0, -4 * q2, -4 * q3, 0.0),
            )
            var f = fg
            var j = jg
            val m = unit(mag)
            if (marg) {
                val bx = b[1]
                val bz = b[3]
                val fb = doubleArrayOf( // (eq. 29)
                    2 * bx * (0.5 - q3 * q3 - q4 * q4) + 2 * bz * (q2 * q4 - q1 * q3) - m[0],
                    2 * bx * (q2 * q3 - q1 * q4) + 2 * bz * (q1 * q2 + q3 * q4) - m[1],
                    2 * bx * (q1 * q3 + q2 * q4) + 2 * bz * (0.5 - q2 * q2 - q3 * q3) - m[2],
                )
                val jb = arrayOf( // (eq. 30)
                    doubleArrayOf(-2 * bz * q3, 2 * bz * q4, -4 * bx * q3 - 2 * bz * q1, -4 * bx * q4 + 2 * bz * q2),
                    doubleArrayOf(-2 * bx * q4 + 2 * bz * q2, 2 * bx * q3 + 2 * bz * q1, 2 * bx * q2 + 2 * bz * q4, -2 * bx * q1 + 2 * bz * q3),
                    doubleArrayOf(2 * bx * q3, 2 * bx * q4 - 4 * bz * q2, 2 * bx * q1 - 4 * bz * q3, 2 * bx * q2),
                )
                f = fg + fb
                j = jg + jb
            }
            // ∇f = Jᵀ f (eq. 34), normalised (eq. 44).
            val grad = DoubleArray(4) { c -> j.indices.sumOf { r -> j[r][c] * f[r] } }
            val qDotEps = unit4(grad)
            if (marg) {
                // ω_ε = 2 q̂* ⊗ q̇_ε (eq. 47), ω_b += ζ ω_ε Δt (eq. 48).
                val omegaEps = product(conjugate(q), qDotEps).map { 2 * it }
                for (k in 0..2) bias[k] += zeta * omegaEps[k + 1] * dt
            }
            val omega = doubleArrayOf(0.0, gyro.x - bias[0], gyro.y - bias[1], gyro.z - bias[2]) // (eq. 49)
            val qDotOmega = product(q, omega).map { 0.5 * it } // (eq. 12)
            q = unit4(DoubleArray(4) { k -> q[k] + (qDotOmega[k] - beta * qDotEps[k]) * dt }) // (eqs. 42–43)
            if (marg) {
                val h = product(product(q, doubleArrayOf(0.0, m[0], m[1], m[2])), conjugate(q)) // (eq. 45)
                b = doubleArrayOf(0.0, sqrt(h[1] * h[1] + h[2] * h[2]), 0.0, h[3]) // (eq. 46)
            }
        }

        fun product(a: DoubleArray, c: DoubleArray) = doubleArrayOf(
            a[0] * c[0] - a[1] * c[1] - a[2] * c[2] - a[3] * c[3],
            a[0] * c[1] + a[1] * c[0] + a[2] * c[3] - a[3] * c[2],
            a[0] * c[2] - a[1] * c[3] + a[2] * c[0] + a[3] * c[1],
            a[0] * c[3] + a[1] * c[2] - a[2] * c[1] + a[3] * c[0],
        )

        fun conjugate(a: DoubleArray) = doubleArrayOf(a[0], -a[1], -a[2], -a[3])
        fun unit(v: Vector3) = v.normalized().toDoubleArray()
        fun unit4(v: DoubleArray): DoubleArray = sqrt(v.sumOf { it * it }).let { n -> DoubleArray(4) { v[it] / n } }
    }

    private fun samples(seed: Long) = MotionSimulator(
        SimulationSettings(
            seed = seed, durationS = 30.0, angularRate = 2.0, gyroBias = Vector3(0.01, -0.02, 0.015),
            gyroNoise = 0.01, accNoise = 0.2, magNoise = 1.0, linearAcceleration = 3.0,
            linearAccelerationWindow = TimeWindow(10.0, 15.0), timestampJitter = 0.0005, dropProbability = 0.01,
        ),
    ).run()

    /** Largest |component difference| between filter and reference over the run. */
    private fun maxDifference(settings: FilterSettings, data: List<SimulatedSample>): Double {
        val marg = settings.mode == FilterMode.MARG
        val filter = MadgwickFilter(settings.copy(outputFrame = WorldFrame.NWU))
        val ref = Reference(settings.beta, settings.zeta ?: 0.0, marg)
        val out = DoubleArray(4)
        var worst = 0.0
        for ((i, s) in data.withIndex()) {
            if (marg) filter.update(s.timestampNs, s.gyro, s.acc, s.mag) else filter.update(s.timestampNs, s.gyro, s.acc)
            if (i > 0) ref.step((s.timestampNs - data[i - 1].timestampNs) * 1e-9, s.gyro, s.acc, s.mag)
            filter.orientationInto(out)
            for (k in 0..3) worst = maxOf(worst, abs(out[k] - ref.q[k]))
            val bias = filter.diagnostics().gyroBias.toDoubleArray()
            for (k in 0..2) worst = maxOf(worst, abs(bias[k] - ref.bias[k]))
        }
        return worst
    }

    @Test
    fun `MARG update with zeta matches the report's equations step by step`() {
        for (seed in 1L..3L) {
            val d = maxDifference(FilterSettings.report(), samples(seed))
            assertTrue(d < 1e-7, "seed $seed: max difference $d")
        }
    }

    @Test
    fun `IMU update matches the report's equations step by step`() {
        val d = maxDifference(FilterSettings.report(FilterMode.IMU), samples(4))
        assertTrue(d < 1e-7, "max difference $d")
    }

    @Test
    fun `MARG update with zeta matches the report's equations on a real recording given by the broad-trial property`() {
        // Opt-in: the recordings are not part of the repository. Example:
        // mvn -pl fusion-core test -Dtest=ReportReferenceTest -Dbroad-trial=TRIAL_DIR (a BROAD trial folder with input.csv.gz)
        val dir = System.getProperty("broad-trial")
        assumeTrue(dir != null, "no -Dbroad-trial given")
        val trial = Trial.load(File(dir!!))
        val data = ArrayList<SimulatedSample>()
        trial.open().use { rows ->
            while (rows.next()) {
                val r = rows.imu
                data += SimulatedSample((rows.timeS * 1e9).roundToLong(), Vector3(r[0], r[1], r[2]), Vector3(r[3], r[4], r[5]), Vector3(r[6], r[7], r[8]), Quaternion.IDENTITY)
            }
        }
        val d = maxDifference(FilterSettings.report(), data)
        println("${trial.name}: ${data.size} steps, max difference $d")
        assertTrue(d < 1e-7, "max difference $d")
    }

    @Test
    fun `the comparison detects a different gain`() {
        // Guards the two tests above against passing vacuously.
        val data = samples(5)
        val filter = MadgwickFilter(FilterSettings.report().copy(beta = 0.05, outputFrame = WorldFrame.NWU))
        val ref = Reference(0.06, FilterSettings.report().zeta!!, marg = true)
        for ((i, s) in data.withIndex()) {
            filter.update(s.timestampNs, s.gyro, s.acc, s.mag)
            if (i > 0) ref.step((s.timestampNs - data[i - 1].timestampNs) * 1e-9, s.gyro, s.acc, s.mag)
        }
        val q = filter.orientation()
        val d = (0..3).maxOf { abs(q.toDoubleArray()[it] - ref.q[it]) }
        assertTrue(d > 1e-4, "difference only $d")
    }
}
