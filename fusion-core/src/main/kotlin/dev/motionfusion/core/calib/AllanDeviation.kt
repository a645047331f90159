/*
 * Overlapping Allan deviation of a sensor's three axes (device frame; rad/s or m/s²) from a
 * long still recording, in one pass with memory independent of the recording's length.
 *
 * For a cluster of m samples (τ = m·τ₀) the overlapping Allan variance is
 *   σ²(τ) = Σ_k (x_{k+2m} − 2·x_{k+m} + x_k)² / (2·τ²·K)
 * over the K terms, x being the running sum of the samples times τ₀ (the angle, for a
 * gyroscope). Cluster sizes are log-spaced (8 a decade). Below 512 samples every k is used;
 * above, clusters of m ∈ [256·D, 512·D) use every D-th k (D a power of two): x is kept at
 * stride D in a ring of 1,025 entries per octave, so the terms still overlap by at least
 * 255/256 of a cluster and the estimate is practically the fully overlapping one.
 */
package dev.motionfusion.core.calib

import dev.motionfusion.core.event.SampleRate
import kotlin.math.floor
import kotlin.math.pow
import kotlin.math.sqrt

/** Feed samples with [add]; read the curve with [curve] once done. */
internal class AllanAccumulator {
    private val levels = Array(MAX_LEVELS) { Level(it) }
    private var count = 0L
    private val first = DoubleArray(3)
    private val prev = DoubleArray(3)
    private val x = DoubleArray(3) // running sums of (sample − first sample), in samples
    private var gaps = 0L
    /** The intervals between samples, gaps left out: the sample interval is their mean. */
    private val clock = SampleRate()
    /** Samples since the last gap, and the most in one stretch between gaps. */
    private var stretch = 0L
    private var longestStretch = 0L
    private var splits = 0L

    /** Samples added. */
    val samples: Long get() = count

    /**
     * Adds one sample at [timestampNs]. The samples are taken as evenly spaced at the mean
     * interval (gaps left out). An interval over five times the mean so far is a gap: the curve is
     * computed over the stretches between gaps, no cluster spanning one, and the rate over the
     * samples that exist. Gaps, timestamps that stall or step back, and non-finite samples
     * (replaced by the previous sample) are counted in [AllanCurve.gaps].
     */
    fun add(timestampNs: Long, vx: Double, vy: Double, vz: Double) {
        if (!(vx.isFinite() && vy.isFinite() && vz.isFinite())) {
            // Hold the previous sample, so the samples stay on their time grid.
            gaps++
            if (count > 0L) add(timestampNs, prev[0], prev[1], prev[2])
            return
        }
        prev[0] = vx; prev[1] = vy; prev[2] = vz
        when (clock.add(timestampNs)) {
            SampleRate.Interval.FIRST -> {
                first[0] = vx; first[1] = vy; first[2] = vz
                for (lv in levels) lv.restart(x) // x_0 = 0: the sum before the first sample
            }
            SampleRate.Interval.STALL -> gaps++
            SampleRate.Interval.GAP -> {
                // A new stretch, whose clusters do not reach back over it.
                gaps++
                splits++
                stretch = 0L
                for (lv in levels) lv.restart(x)
            }
            SampleRate.Interval.SAMPLE -> {}
        }
        x[0] += vx - first[0]; x[1] += vy - first[1]; x[2] += vz - first[2]
        count++
        stretch++
        if (stretch > longestStretch) longestStretch = stretch
        // Sample index k = stretch (in the current stretch); level L stores x_k when k is a multiple of 2^L.
        var level = 0
        while (level < MAX_LEVELS && stretch % (1L shl level) == 0L) {
            levels[level].push(x)
            level++
        }
    }

    /** The Allan deviation from what was added; τ from the mean sample interval. */
    fun curve(): AllanCurve {
        val tau0 = if (clock.intervals > 0) clock.intervalSumNs * 1e-9 / clock.intervals else Double.NaN
        val ms = ArrayList<Long>()
        val dev = Array(3) { ArrayList<Double>() }
        val weights = ArrayList<Long>()
        for (lv in levels) {
            for ((j, m) in lv.clusters.withIndex()) {
                val n = lv.terms[j]
                if (n < 2 || 3 * m > longestStretch) continue // at least three clusters' worth of data
                ms += m
                // Clusters behind the point: N − 2m in one stretch; over several, the terms summed (each D apart).
                weights += if (splits == 0L) count + 1 - 2 * m else n * lv.d
                for (a in 0 until 3) dev[a] += sqrt(lv.sums[3 * j + a] / (2.0 * m * m * n)) // x in samples: τ₀ cancels
            }
        }
        val order = ms.indices.sortedBy { ms[it] }
        return AllanCurve(
            tau = order.map { ms[it] * tau0 }.toDoubleArray(),
            deviation = Array(3) { a -> order.map { dev[a][it] }.toDoubleArray() },
            clusterCounts = order.map { weights[it] }.toLongArray(),
            samples = count,
            rateHz = 1.0 / tau0,
            gaps = gaps,
        )
    }

    /** One octave: x at stride D = 2^L in a ring, and the sums of squared second differences of its clusters. */
    private class Level(level: Int) {
        val d = 1L shl level
        /** Cluster sizes in units of D handled here: all log-spaced m in [1, 512) at level 0, [256·D, 512·D) above. */
        val units: IntArray
        val clusters: LongArray
        val sums: DoubleArray
        val terms: LongArray
        private val ring = DoubleArray(3 * RING)
        private var stored = 0L

        init {
            val lo = if (level == 0) 1L else 256L * d
            val hi = 512L * d
            val ms = CLUSTER_SIZES.filter { it in lo until hi }.map { maxOf(1L, Math.round(it.toDouble() / d)) }.distinct()
            units = ms.map { it.toInt() }.toIntArray()
            clusters = ms.map { it * d }.toLongArray()
            sums = DoubleArray(3 * units.size)
            terms = LongArray(units.size)
        }

        /** Starts a new stretch at the sum [x] before its first sample: no term reaches back before it. */
        fun restart(x: DoubleArray) {
            stored = 0L
            push(x)
        }

        fun push(x: DoubleArray) {
            val at = (stored % RING).toInt()
            ring[3 * at] = x[0]; ring[3 * at + 1] = x[1]; ring[3 * at + 2] = x[2]
            stored++
            for (j in units.indices) {
                val u = units[j]
                if (stored <= 2L * u) continue
                val b = ((stored - 1 - u) % RING).toInt()
                val c = ((stored - 1 - 2L * u) % RING).toInt()
                for (a in 0 until 3) {
                    val dd = ring[3 * at + a] - 2.0 * ring[3 * b + a] + ring[3 * c + a]
                    sums[3 * j + a] += dd * dd
                }
                terms[j]++
            }
        }
    }

    private companion object {
        const val RING = 1025
        /** Strides up to 2^23 samples: clusters up to 4·10⁹ samples (about 8 months at 200 Hz). */
        const val MAX_LEVELS = 24
        /** Log-spaced cluster sizes, 8 a decade, from 1 sample up. */
        val CLUSTER_SIZES: List<Long> = (0..(8 * 13)).map { floor(10.0.pow(it / 8.0)).toLong() }.distinct()
    }
}

/**
 * An Allan deviation curve: [deviation] per axis (x, y, z) at cluster times [tau] (s), in the
 * sensor's unit (rad/s, m/s²).
 */
public class AllanCurve(
    public val tau: DoubleArray,
    public val deviation: Array<DoubleArray>,
    /** Number of overlapping clusters behind each point (N − 2m): its statistical weight. */
    public val clusterCounts: LongArray,
    public val samples: Long,
    public val rateHz: Double,
    /** Intervals over five times the mean, stalled or backward timestamps, non-finite samples (held at the previous one) (the analysis assumes even sampling). */
    public val gaps: Long,
) {
    /** The noise terms of each axis. */
    public fun fits(): List<NoiseTerms> = (0 until 3).map { NoiseTerms.fit(tau, deviation[it], clusterCounts) }
}

/**
 * Noise terms read off an Allan deviation curve (IEEE Std 952 slopes):
 *
 * - [whiteNoise] N: the line of slope −½ (angle or velocity random walk) read at τ = 1 s;
 *   the noise density in unit/√Hz (rad/s/√Hz, m/s²/√Hz).
 * - [biasInstability] B: the flat minimum divided by √(2·ln 2/π) ≈ 0.664, in the sensor's unit,
 *   at [biasInstabilityTau].
 * - [randomWalk] K: the line of slope +½ (rate or acceleration random walk) read at τ = 3 s,
 *   in unit/s/√Hz; NaN when the curve never rises (recording too short to show it), with
 *   [randomWalkUpperBound] from the last point instead.
 *
 * The two lines are fitted together with a flat floor, σ²(τ) = N²/τ + c + K²·τ/3, by weighted
 * least squares over the curve from τ = 4 samples up, so each term is read where it dominates
 * without choosing a region by hand.
 */
public data class NoiseTerms(
    val whiteNoise: Double,
    val biasInstability: Double,
    val biasInstabilityTau: Double,
    val randomWalk: Double,
    val randomWalkUpperBound: Double,
) {
    public companion object {
        /** √(2·ln 2 / π): the flicker floor of the Allan deviation relative to B. */
        public const val FLICKER_FACTOR: Double = 0.664

        internal fun fit(tau: DoubleArray, sigma: DoubleArray, clusters: LongArray): NoiseTerms {
            val n = tau.size
            if (n < 3) return NoiseTerms(Double.NaN, Double.NaN, Double.NaN, Double.NaN, Double.NaN)
            var iMin = 0
            for (i in 0 until n) if (sigma[i] < sigma[iMin]) iMin = i
            // Points from 4 samples up: below, a sensor's own low-pass filter lowers the curve.
            val use = (0 until n).filter { tau[it] >= 3.5 * tau[0] && sigma[it] > 0.0 && sigma[it].isFinite() }
            val p = if (use.size >= 3) modelFit(use.map { tau[it] }, use.map { sigma[it] * sigma[it] }, use.map { clusters[it] * tau[0] / tau[it] }) else null
            val white = p?.let { if (it[0] > 0.0) sqrt(it[0]) else Double.NaN } ?: Double.NaN
            val walk = p?.let { if (it[2] > 0.0) sqrt(3.0 * it[2]) else Double.NaN } ?: Double.NaN
            val upper = sigma[n - 1] * sqrt(3.0 / tau[n - 1])
            return NoiseTerms(white, sigma[iMin] / FLICKER_FACTOR, tau[iMin], walk, upper)
        }

        /**
         * Weighted least squares of σ²(τ) = a/τ + c + b·τ (white noise N² = a, a flat floor c,
         * random walk K² = 3b) with non-negative coefficients: every subset of the three terms is
         * fitted and the best with all coefficients positive is kept. Weights: the number of
         * independent clusters over the model's σ⁴ (the relative variance of an Allan variance
         * estimate is about 2 / that number), refined three times. Returns [a, c, b] or null.
         */
        private fun modelFit(tau: List<Double>, s2: List<Double>, dof: List<Double>): DoubleArray? {
            val n = tau.size
            val basis = arrayOf({ t: Double -> 1.0 / t }, { _: Double -> 1.0 }, { t: Double -> t })
            var model = s2.toDoubleArray()
            var best: DoubleArray? = null
            repeat(3) {
                val w = DoubleArray(n) { dof[it] / (model[it] * model[it]) }
                best = null
                var bestCost = Double.POSITIVE_INFINITY
                for (mask in 1 until 8) {
                    val terms = (0 until 3).filter { mask and (1 shl it) != 0 }
                    val k = terms.size
                    val ata = DoubleArray(k * k)
                    val atb = DoubleArray(k)
                    for (i in 0 until n) {
                        for (r in 0 until k) {
                            val fr = basis[terms[r]](tau[i])
                            atb[r] += w[i] * fr * s2[i]
                            for (c in 0 until k) ata[r * k + c] += w[i] * fr * basis[terms[c]](tau[i])
                        }
                    }
                    val x = solveLinear(ata, atb, k) ?: continue
                    if (x.any { !(it > 0.0) }) continue
                    val coef = DoubleArray(3)
                    terms.forEachIndexed { j, t -> coef[t] = x[j] }
                    var cost = 0.0
                    for (i in 0 until n) {
                        val f = coef[0] / tau[i] + coef[1] + coef[2] * tau[i]
                        cost += w[i] * (s2[i] - f) * (s2[i] - f)
                    }
                    if (cost < bestCost) { bestCost = cost; best = coef }
                }
                val b = best ?: return null
                model = DoubleArray(n) { b[0] / tau[it] + b[1] + b[2] * tau[it] }
            }
            return best
        }
    }
}
