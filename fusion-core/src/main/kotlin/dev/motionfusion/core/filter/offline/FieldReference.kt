/*
 * The recording's own undisturbed field, for the offline combination and the heading smoother: a check of
 * each magnetometer reading against the medians over the whole recording (non-causal; the causal filter's
 * MagneticDisturbanceDetector learns its reference as it goes). µT, device frame; orientation sensor → ENU.
 */
package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.SensorRanges
import dev.motionfusion.core.unitQuaternionUp
import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.asin
import kotlin.math.exp
import kotlin.math.sin
import kotlin.math.sqrt

/**
 * The recording's own undisturbed field, for the offline combination: the medians of the magnetometer's
 * magnitude (µT) and dip angle (the angle below the horizontal, from the first pass's orientation) over the
 * whole recording, kept as histograms (memory fixed whatever the length). A reading is disturbed when its
 * magnitude departs from that median by more than FilterSettings.magNormTolerance (relative) or its dip, by
 * the orientation given, by more than magDipTolerance: the causal filter's own tolerances. It also keeps the
 * magnitudes read while the device moves (the first pass's rest detector), for [motionSpread]. Frames: field
 * in the device frame, orientation sensor → ENU.
 */
internal class FieldReference(settings: FilterSettings) {
    private val normTolerance = settings.magNormTolerance
    private val dipTolerance = settings.magDipTolerance

    /** The rate at which the heading correction pulls an error out, 1/s (headingGain; the default's with the report's step). */
    private val rate = settings.headingGain ?: DEFAULT_RATE
    private val norms = IntArray(NORM_BINS)
    private val motionNorms = IntArray(NORM_BINS)
    private var motionCount = 0L

    /**
     * The spread of the field's magnitude while the device moved: 1.4826 × its median absolute deviation, relative
     * to its median (so a standard deviation for normal noise); 0 without such readings. Set by [settle].
     */
    var motionSpread = 0.0
        private set

    // Sines of the dip (monotonic in the dip, so their median is the sine of the median dip): no arcsine per reading.
    private val sinDips = IntArray(SIN_BINS)
    private var count = 0L
    private var normLow = Double.NaN
    private var normHigh = Double.NaN
    private var sinLow = Double.NaN
    private var sinHigh = Double.NaN
    private var decayNs = -1L
    private var decayFactor = 1.0

    /** Takes the reading [m] at the orientation [q]; [rest]: the rest detector's flag then. */
    fun add(m: DoubleArray, q: DoubleArray, rest: Boolean) {
        if (!SensorRanges.isEarthField(m[0], m[1], m[2]) || q[0].isNaN()) return
        val n = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2])
        val bin = (n / NORM_BIN).toInt().coerceIn(0, NORM_BINS - 1)
        norms[bin]++
        if (!rest) {
            motionNorms[bin]++
            motionCount++
        }
        sinDips[((sinDip(m, n, q) + 1.0) / SIN_BIN).toInt().coerceIn(0, SIN_BINS - 1)]++
        count++
    }

    /** Fixes the medians and the limits around them; before any reading was added nothing is disturbed. */
    fun settle() {
        if (count == 0L) return
        if (motionCount > 0L) {
            // The median absolute deviation from the histogram: the deviations' histogram in the same bins.
            val mid = median(motionNorms, motionCount)
            val deviations = IntArray(NORM_BINS)
            for (i in motionNorms.indices) if (motionNorms[i] != 0) deviations[abs(i - mid)] += motionNorms[i]
            motionSpread = MAD_TO_SD * median(deviations, motionCount) / (mid + 0.5)
        }
        val norm = (median(norms, count) + 0.5) * NORM_BIN
        normLow = norm * (1.0 - normTolerance)
        normHigh = norm * (1.0 + normTolerance)
        val dip = asin(((median(sinDips, count) + 0.5) * SIN_BIN - 1.0).coerceIn(-1.0, 1.0))
        sinLow = sin(maxOf(-PI / 2, dip - dipTolerance))
        sinHigh = sin(minOf(PI / 2, dip + dipTolerance))
    }

    fun disturbed(m: DoubleArray, q: DoubleArray): Boolean {
        if (normLow.isNaN() || q[0].isNaN()) return false
        val n = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2])
        if (!(n > 0.0) || n.isInfinite()) return false
        if (n < normLow || n > normHigh) return true
        val s = sinDip(m, n, q)
        return s < sinLow || s > sinHigh
    }

    /** [recent] after [ns] more of a pass without a disturbed reading (0 once below 10⁻⁴). */
    fun decay(recent: Double, ns: Long): Double {
        if (recent == 0.0) return 0.0
        if (ns != decayNs) {
            decayNs = ns
            decayFactor = exp(-rate * ns * 1e-9)
        }
        val r = recent * decayFactor
        return if (r < 1e-4) 0.0 else r
    }

    private fun median(h: IntArray, count: Long): Int {
        var seen = 0L
        for (i in h.indices) {
            seen += h[i]
            if (2 * seen >= count) return i
        }
        return h.size - 1
    }

    companion object {
        const val NORM_BIN = 0.1
        const val NORM_BINS = 20_000
        const val SIN_BINS = 4000
        const val SIN_BIN = 2.0 / SIN_BINS
        const val DEFAULT_RATE = 0.05

        /** A normal distribution's standard deviation over its median absolute deviation. */
        const val MAD_TO_SD = 1.4826

        /** Sine of the dip angle: of [m] (magnitude [n]) below the horizontal of the orientation [q] (sensor → ENU). */
        fun sinDip(m: DoubleArray, n: Double, q: DoubleArray): Double {
            return unitQuaternionUp(q, 0) { ux, uy, uz -> -(m[0] * ux + m[1] * uy + m[2] * uz) / n }
        }
    }
}
