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
            val b = distortion(t)
            val ex = b[0]
            val ey = 20.0 + b[1]
            val ez = -43.0 + b[2]
            // Into the device frame: turned by −ψ about up.
            val mx = cos(psi) * ex + sin(psi) * ey
            val my = -sin(psi) * ex + cos(psi) * ey
            filter.update((t * 1e9).toLong(), 0.0, 0.0, rate(t), 0.0, 0.0, 9.81, mx, my, ez)
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

    /** Outside for 20 s, then through a building whose steel adds up to 12 µT, changing over tens of seconds. */
    private val walkIn: (Double) -> DoubleArray = { t ->
        val u = maxOf(0.0, t - 20.0)
        doubleArrayOf(12.0 * sin(2 * PI * u / 23.0), 12.0 * sin(2 * PI * u / 31.0), 8.0 * sin(2 * PI * u / 17.0))
    }

    private val clean: (Double) -> DoubleArray = { doubleArrayOf(0.0, 0.0, 0.0) }

    @Test
    fun `in a wandering field the heading follows the gyroscope`() {
        val without = run(MadgwickFilter(FilterSettings()), 140.0, 20.0, walkIn)
        val with = run(MadgwickFilter(FilterSettings(magTrustSpread = 0.01)), 140.0, 20.0, walkIn)
        println(String.format(Locale.ROOT, "wandering field: heading RMS %.2f° without the trust, %.2f° with it", without, with))
        assertTrue(without > 2.0, "the wandering field should pull the default filter's heading: $without°")
        assertTrue(with < without / 2, "with the trust $with°, without $without°")
    }

    @Test
    fun `in a clean field the trust changes nothing`() {
        val a = MadgwickFilter(FilterSettings())
        val b = MadgwickFilter(FilterSettings(magTrustSpread = 0.01))
        val trace = mutableListOf<Double>()
        run(a, 60.0, 0.0, clean)
        run(b, 60.0, 0.0, clean, trace)
        assertEquals(1.0, trace.min())
        assertArrayEquals(DoubleArray(4).also { a.orientationInto(it) }, DoubleArray(4).also { b.orientationInto(it) })
    }

    @Test
    fun `the trust comes back once the field is clean again`() {
        val f = MadgwickFilter(FilterSettings(magTrustSpread = 0.01))
        val trace = mutableListOf<Double>()
        // 20 s outside, 40 s in the building, then 90 s outside again.
        run(f, 150.0, 0.0, { t -> if (t < 60.0) walkIn(t) else clean(t) }, trace)
        val at = { s: Double -> trace[(s * rateHz).toInt()] }
        assertTrue(at(59.0) < 0.05, "trust in the building: ${at(59.0)}")
        assertEquals(1.0, at(150.0), "trust 90 s after leaving it")
    }
}
