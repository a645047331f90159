package dev.motionfusion.core.filter

import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.Locale
import kotlin.math.PI
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.sin
import kotlin.math.sqrt

/**
 * The magnetic trust (magTrustSpread) on a phone held level and turned back and forth, its gyroscope exact: in a
 * field that a building's steel distorts more or less as the phone is carried through it, the heading follows the gyroscope instead of the
 * field; in a clean field nothing changes; once the field is clean again the trust comes back.
 */
class MagneticTrustTest {
    private val rateHz = 100.0

    /** Heading (rad about up, ENU) of the phone at [t] s: turned from 0 to 1.9 rad and back every 20 s. */
    private fun heading(t: Double) = 0.3 * (1.0 - cos(2 * PI * t / 20.0)) / (2 * PI / 20.0)

    /** Its rate, rad/s: the derivative of [heading]. */
    private fun rate(t: Double) = 0.3 * sin(2 * PI * t / 20.0)

    /**
     * Runs [filter] for [seconds] s in the earth's field (20 µT north, 43 µT down) plus [distortion] (ENU, µT, at
     * each time: what a building adds); returns the RMS heading error (degrees) from [scoreFrom] s on.
     */
    private fun run(filter: MadgwickFilter, seconds: Double, scoreFrom: Double, distortion: (Double) -> DoubleArray, trace: MutableList<Double>? = null): Double {
        var sum = 0.0
        var n = 0
        val steps = (seconds * rateHz).toInt()
        for (i in 0..steps) {
            val t = i / rateHz
            val psi = heading(t)
            step(filter, t, distortion)
            trace?.add(filter.magneticTrust)
            if (t >= scoreFrom) {
                val q = filter.orientation()
                val yaw = atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))
                var e = yaw - psi
                while (e > PI) e -= 2 * PI
                while (e < -PI) e += 2 * PI
                sum += e * e
                n++
            }
        }
        return sqrt(sum / n) * 180 / PI
    }

    /** One sample at [t] s: the exact gyroscope, level, the earth's field plus [distortion] in the device frame. */
    private fun step(filter: MadgwickFilter, t: Double, distortion: (Double) -> DoubleArray) {
        val psi = heading(t)
        val b = distortion(t)
        val ex = b[0]
        val ey = 20.0 + b[1]
        // Into the device frame: turned by −ψ about up.
        val mx = cos(psi) * ex + sin(psi) * ey
        val my = -sin(psi) * ex + cos(psi) * ey
        filter.update((t * 1e9).toLong(), 0.0, 0.0, rate(t), 0.0, 0.0, 9.81, mx, my, -43.0 + b[2])
    }

    /** Outside for 20 s, then through a building whose steel adds up to 12 µT, changing over tens of seconds. */
    private val walkIn: (Double) -> DoubleArray = { t ->
        val u = maxOf(0.0, t - 20.0)
        doubleArrayOf(12.0 * sin(2 * PI * u / 23.0), 12.0 * sin(2 * PI * u / 31.0), 8.0 * sin(2 * PI * u / 17.0))
    }

    private val clean: (Double) -> DoubleArray = { doubleArrayOf(0.0, 0.0, 0.0) }

    @Test
    fun `in a wandering field the heading follows the gyroscope`() {
        val without = run(MadgwickFilter(FilterSettings()), 140.0, 20.0, walkIn)
        val with = run(MadgwickFilter(FilterSettings(magTrustSpread = 0.005)), 140.0, 20.0, walkIn)
        println(String.format(Locale.ROOT, "wandering field: heading RMS %.2f° without the trust, %.2f° with it", without, with))
        assertTrue(without > 2.0, "the wandering field should pull the default filter's heading: $without°")
        assertTrue(with < without / 2, "with the trust $with°, without $without°")
    }

    /** Records the factors the checks before it left on each step. */
    private class Factors : Check<Unit> {
        var heading = 1.0
        var bias = 1.0

        override fun check(s: Step) {
            heading = s.headingFactor
            bias = s.biasFactor
        }

        override fun state() = Unit
        override fun restore(state: Unit) = Unit
        override fun reset() = Unit
    }

    @Test
    fun `in a wandering field the bias estimate in motion learns far less than the heading`() {
        // The bias is what carries the heading through the building: the field may steer the heading a little
        // (the factor r) but teaches the bias with r³, the heading step's r times r².
        val factors = Factors()
        val f = MadgwickFilter(FilterSettings(magTrustSpread = 0.005)).withChecks(factors)
        var checked = 0
        val steps = (60.0 * rateHz).toInt()
        for (i in 0..steps) {
            val t = i / rateHz
            step(f, t, walkIn)
            if (t > 40.0) {
                val r = f.magneticTrust
                assertTrue(r < 0.5, "trust at $t s in the building: $r")
                assertEquals(r, factors.heading, 1e-15)
                assertEquals(r * r, factors.bias, 1e-15)
                checked++
            }
        }
        assertTrue(checked > 1000)
        // The gyroscope is exact, so any bias learnt in motion is the building's field speaking through it.
        val without = MadgwickFilter(FilterSettings())
        run(without, 140.0, 20.0, walkIn)
        val with = MadgwickFilter(FilterSettings(magTrustSpread = 0.005))
        run(with, 140.0, 20.0, walkIn)
        val deg = { g: MadgwickFilter -> g.diagnostics().gyroBias.let { sqrt(it.x * it.x + it.y * it.y + it.z * it.z) } * 180 / PI }
        println(String.format(Locale.ROOT, "wandering field: bias learnt %.4f°/s without the trust, %.4f°/s with it", deg(without), deg(with)))
        assertTrue(deg(with) < deg(without) / 5, "with the trust ${deg(with)}°/s, without ${deg(without)}°/s")
    }

    @Test
    fun `in a clean field the trust changes nothing`() {
        val a = MadgwickFilter(FilterSettings())
        val b = MadgwickFilter(FilterSettings(magTrustSpread = 0.005))
        val trace = mutableListOf<Double>()
        run(a, 60.0, 0.0, clean)
        run(b, 60.0, 0.0, clean, trace)
        assertEquals(1.0, trace.min())
        assertArrayEquals(DoubleArray(4).also { a.orientationInto(it) }, DoubleArray(4).also { b.orientationInto(it) })
    }

    @Test
    fun `the trust comes back once the field is clean again`() {
        val f = MadgwickFilter(FilterSettings(magTrustSpread = 0.005))
        val trace = mutableListOf<Double>()
        val held = mutableListOf<Boolean>()
        // 20 s outside, 40 s in the building, then 90 s outside again.
        val walk = { t: Double -> if (t < 60.0) walkIn(t) else clean(t) }
        for (i in 0..(150.0 * rateHz).toInt()) {
            step(f, i / rateHz, walk)
            trace.add(f.magneticTrust)
            held.add(f.diagnostics().magneticDisturbance)
        }
        val at = { s: Double -> (s * rateHz).toInt() }
        assertTrue(trace[at(59.0)] < 0.05, "trust in the building: ${trace[at(59.0)]}")
        assertEquals(1.0, trace[at(150.0)], "trust 90 s after leaving it")
        // The diagnostics (the app's "holding the heading on the gyroscope") say so while the gain is under a quarter.
        for (i in trace.indices) assertEquals(trace[i] < 0.25, held[i], "shown as held at ${i / rateHz} s, trust ${trace[i]}")
        assertTrue(held[at(59.0)] && !held[at(10.0)] && !held[at(150.0)])
    }
}
