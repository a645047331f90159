package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.sim.SimulatedSample
import org.junit.jupiter.api.Assertions.assertEquals
import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.atan
import kotlin.math.min
import kotlin.math.sqrt

/** Helpers shared by the filter tests: run a filter over simulated samples and measure errors in degrees. */
internal object SimulatedRuns {
    /** One entry per sample: the filter's ENU estimate after it. */
    fun run(filter: MadgwickFilter, data: List<SimulatedSample>, useMag: Boolean = true): List<Quaternion> = data.map { s ->
        if (useMag) filter.update(s.timestampNs, s.gyro, s.acc, s.mag) else filter.update(s.timestampNs, s.gyro, s.acc)
        filter.orientation()
    }

    /** e = est ⊗ truth* (earth frame). */
    private fun error(est: Quaternion, truth: Quaternion) = est * truth.conjugate()

    fun totalDeg(est: Quaternion, truth: Quaternion): Double = Math.toDegrees(est.angleTo(truth))

    fun headingDeg(est: Quaternion, truth: Quaternion): Double = error(est, truth).let { e -> Math.toDegrees(2.0 * atan(abs(e.z / e.w))) }

    fun inclinationDeg(est: Quaternion, truth: Quaternion): Double =
        error(est, truth).let { e -> Math.toDegrees(2.0 * acos(min(1.0, sqrt(e.w * e.w + e.z * e.z)))) }

    /** RMS of [metric] over samples [from] until [to] (indices). */
    fun rms(est: List<Quaternion>, data: List<SimulatedSample>, from: Int, to: Int = data.size, metric: (Quaternion, Quaternion) -> Double): Double =
        sqrt((from until to).sumOf { metric(est[it], data[it].truth).let { v -> v * v } } / (to - from))

    fun max(est: List<Quaternion>, data: List<SimulatedSample>, from: Int, to: Int = data.size, metric: (Quaternion, Quaternion) -> Double): Double =
        (from until to).maxOf { metric(est[it], data[it].truth) }

    /**
     * A run over [data] stopped after [split] samples and continued in a new filter from the first one's state ends
     * in the same state and orientation as the unbroken run.
     */
    fun assertSplitRunEqualsWhole(settings: FilterSettings, data: List<SimulatedSample>, split: Int) {
        val whole = MadgwickFilter(settings)
        data.forEach { whole.update(it.timestampNs, it.gyro, it.acc, it.mag) }
        val first = MadgwickFilter(settings)
        data.take(split).forEach { first.update(it.timestampNs, it.gyro, it.acc, it.mag) }
        val second = MadgwickFilter(settings)
        second.restore(first.state())
        data.drop(split).forEach { second.update(it.timestampNs, it.gyro, it.acc, it.mag) }
        assertEquals(whole.state(), second.state())
        assertEquals(whole.orientation(), second.orientation())
    }

    /** Index of the first sample at or after [timeS]. */
    fun index(data: List<SimulatedSample>, timeS: Double): Int = data.indexOfFirst { it.timestampNs >= (timeS * 1e9).toLong() }
}
