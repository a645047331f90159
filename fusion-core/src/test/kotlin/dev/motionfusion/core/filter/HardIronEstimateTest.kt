package dev.motionfusion.core.filter

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.SimulatedRuns.headingDeg
import dev.motionfusion.core.filter.SimulatedRuns.index
import dev.motionfusion.core.filter.SimulatedRuns.rms
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.util.Locale
import kotlin.math.PI
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.exp
import kotlin.math.sin
import kotlin.math.sqrt

/**
 * The hard-iron estimate (hardIronThreshold) on a phone held level and turned back and forth, its gyroscope exact,
 * in the earth's field (20 µT north, 43 µT down): an offset fixed to the phone is learnt from the field's turning
 * against the gyroscope's and taken off; a calibrated magnetometer, a magnet passing by and a raw magnetometer's
 * reading beyond the earth's field leave the estimate as it was without it.
 */
class HardIronEstimateTest {
    private val rateHz = 100.0

    /** Heading (rad about up, ENU) at [t] s: turned from 0 to 1.9 rad and back every 20 s. */
    private fun heading(t: Double) = 0.3 * (1.0 - cos(2 * PI * t / 20.0)) / (2 * PI / 20.0)

    private fun rate(t: Double) = 0.3 * sin(2 * PI * t / 20.0)

    /**
     * Runs [filter] for [seconds] s with [offset] (device frame, µT) added to every reading and [world] (ENU, µT, at
     * each time) added to the earth's field; returns the RMS heading error (degrees) from [scoreFrom] s on and
     * each step's orientation into [quaternions] if given.
     */
    private fun run(
        filter: MadgwickFilter, seconds: Double, scoreFrom: Double, offset: DoubleArray,
        world: (Double) -> DoubleArray = { doubleArrayOf(0.0, 0.0, 0.0) }, quaternions: MutableList<DoubleArray>? = null,
    ): Double {
        var sum = 0.0
        var n = 0
        for (i in 0..(seconds * rateHz).toInt()) {
            val t = i / rateHz
            val psi = heading(t)
            val w = world(t)
            val ex = w[0]
            val ey = 20.0 + w[1]
            val mx = cos(psi) * ex + sin(psi) * ey + offset[0]
            val my = -sin(psi) * ex + cos(psi) * ey + offset[1]
            filter.update((t * 1e9).toLong(), 0.0, 0.0, rate(t), 0.0, 0.0, 9.81, mx, my, -43.0 + w[2] + offset[2])
            val q = filter.orientation()
            quaternions?.add(doubleArrayOf(q.w, q.x, q.y, q.z))
            if (t >= scoreFrom) {
                var e = atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z)) - psi
                while (e > PI) e -= 2 * PI
                while (e < -PI) e += 2 * PI
                sum += e * e
                n++
            }
        }
        return sqrt(sum / n) * 180 / PI
    }

    private fun offsetOf(filter: MadgwickFilter) = filter.diagnostics().magnetometerOffset.let { doubleArrayOf(it.x, it.y, it.z) }

    @Test
    fun `an offset fixed to the phone is learnt and taken off`() {
        val b = doubleArrayOf(9.0, -6.0, 0.0)
        val with = MadgwickFilter(FilterSettings())
        val withError = run(with, 120.0, 60.0, b)
        val withoutError = run(MadgwickFilter(FilterSettings(hardIronThreshold = null)), 120.0, 60.0, b)
        val taken = offsetOf(with)
        println(String.format(Locale.ROOT, "offset (9, -6, 0) µT: taken off (%.2f, %.2f, %.2f); heading RMS %.2f° with the estimate, %.2f° without",
            taken[0], taken[1], taken[2], withError, withoutError))
        // The estimate shrunk by the threshold (1.5 µT) along its direction.
        val shrink = 1.0 - FilterSettings().hardIronThreshold!! / sqrt(81.0 + 36.0)
        assertEquals(9.0 * shrink, taken[0], 0.3)
        assertEquals(-6.0 * shrink, taken[1], 0.3)
        assertEquals(0.0, taken[2], 0.3)
        assertTrue(withoutError > 10.0, "the offset should turn the heading without the estimate: $withoutError°")
        assertTrue(withError < withoutError / 4, "with the estimate $withError°, without $withoutError°")
    }

    @Test
    fun `older turns forgotten over a few seconds still give an estimate`() {
        // The first estimate waits for 10 s of windows counted as they close, not as they are forgotten.
        val b = doubleArrayOf(9.0, -6.0, 0.0)
        val filter = MadgwickFilter(FilterSettings(hardIronTime = 5.0))
        run(filter, 60.0, 0.0, b)
        val taken = offsetOf(filter)
        assertTrue(sqrt(taken[0] * taken[0] + taken[1] * taken[1]) > 5.0, "taken off: ${taken.toList()}")
    }

    @Test
    fun `a calibrated magnetometer gives the filter's estimate unchanged`() {
        val with = mutableListOf<DoubleArray>()
        val without = mutableListOf<DoubleArray>()
        val filter = MadgwickFilter(FilterSettings())
        run(filter, 120.0, 0.0, doubleArrayOf(0.0, 0.0, 0.0), quaternions = with)
        run(MadgwickFilter(FilterSettings(hardIronThreshold = null)), 120.0, 0.0, doubleArrayOf(0.0, 0.0, 0.0), quaternions = without)
        assertTrue(offsetOf(filter).all { it == 0.0 }, "taken off: ${offsetOf(filter).toList()}")
        for (i in with.indices) assertArrayEquals(without[i], with[i], "step $i")
    }

    @Test
    fun `a magnet passing by is not taken for an offset`() {
        // 40 µT along east for a few seconds, three times: fixed in the world, not to the phone.
        val magnet: (Double) -> DoubleArray = { t ->
            val a = 40.0 * (exp(-(t - 30.0) * (t - 30.0)) + exp(-(t - 55.0) * (t - 55.0)) + exp(-(t - 80.0) * (t - 80.0)))
            doubleArrayOf(a, 0.0, 0.0)
        }
        val filter = MadgwickFilter(FilterSettings())
        run(filter, 100.0, 0.0, doubleArrayOf(0.0, 0.0, 0.0), magnet)
        val taken = offsetOf(filter)
        assertTrue(sqrt(taken[0] * taken[0] + taken[1] * taken[1] + taken[2] * taken[2]) < 0.5, "taken off: ${taken.toList()}")
    }

    @Test
    fun `a raw magnetometer's reading beyond the earth's field stays out`() {
        // A raw magnetometer offset by hundreds of µT (ADVIO's iPhone's): the filter runs without the field, as before.
        val raw = doubleArrayOf(192.8, 180.2, -582.2)
        val with = mutableListOf<DoubleArray>()
        val without = mutableListOf<DoubleArray>()
        val filter = MadgwickFilter(FilterSettings())
        run(filter, 60.0, 0.0, raw, quaternions = with)
        run(MadgwickFilter(FilterSettings(hardIronThreshold = null)), 60.0, 0.0, raw, quaternions = without)
        for (i in with.indices) assertArrayEquals(without[i], with[i], "step $i")
        // Nothing is taken off, and the diagnostics say so (the estimate itself is near the offset).
        assertTrue(offsetOf(filter).all { it == 0.0 }, "reported taken off: ${offsetOf(filter).toList()}")
    }

    /** The simulated phone of FilterBehaviourTest (turning at 1 rad/s, gyroscope biased) with a 36-µT magnet on it during [magnet]. */
    private fun magnetOn(magnet: TimeWindow) = MotionSimulator(
        SimulationSettings(
            durationS = 300.0, gyroBias = Vector3(0.02, -0.01, 0.015), restWindows = listOf(TimeWindow(0.0, 8.0)),
            hardIron = Vector3(30.0, -20.0, 10.0), hardIronWindow = magnet,
        ),
    ).run()

    @Test
    fun `a magnet kept on the phone is taken off within a minute`() {
        val data = magnetOn(TimeWindow(0.0, 300.0))
        val with = MadgwickFilter(FilterSettings())
        val withError = rms(SimulatedRuns.run(with, data), data, index(data, 100.0), metric = ::headingDeg)
        val withoutError = rms(SimulatedRuns.run(MadgwickFilter(FilterSettings(hardIronThreshold = null)), data), data, index(data, 100.0), metric = ::headingDeg)
        println(String.format(Locale.ROOT, "magnet kept on: heading RMS 100-300 s %.2f° with the estimate, %.2f° without", withError, withoutError))
        assertTrue(withError < 3.0, "with the estimate $withError°")
        assertTrue(withoutError > 30.0, "without the estimate $withoutError°")
    }

    @Test
    fun `a magnet on the phone for a minute is followed on and off`() {
        // A case's magnet, a car mount: on from 20 s to 80 s. The estimate learns it, and once it is off the recent
        // windows fit the recent estimate far better than the whole recording's, which starts again from them.
        val data = magnetOn(TimeWindow(20.0, 80.0))
        val with = MadgwickFilter(FilterSettings())
        val withError = rms(SimulatedRuns.run(with, data), data, index(data, 20.0), metric = ::headingDeg)
        val withoutError = rms(SimulatedRuns.run(MadgwickFilter(FilterSettings(hardIronThreshold = null)), data), data, index(data, 20.0), metric = ::headingDeg)
        println(String.format(Locale.ROOT, "magnet on 20-80 s: heading RMS 20-300 s %.2f° with the estimate, %.2f° without", withError, withoutError))
        assertTrue(withError < 0.75 * withoutError, "with the estimate $withError°, without $withoutError°")
        assertTrue(offsetOf(with).all { kotlin.math.abs(it) < 0.5 }, "taken off at the end: ${offsetOf(with).toList()}")
    }
}
