/*
 * Two recordings of one motion put on one clock by their gyroscopes (docs/SYNC.md): phones held
 * together and shaken, or tapped, turn at the same rate at the same instant whatever their frames,
 * so the magnitudes of their angular velocities match once one is shifted by the offset between
 * their clocks. The shift is found by normalised cross-correlation, first on a coarse grid over the
 * whole search range, then on the finer of the two sample periods around the best coarse lag, and
 * refined between grid points by a parabola through the peak.
 */
package dev.motionfusion.core.sync

import kotlin.math.sqrt

/**
 * What [GyroAlignment.align] found.
 *
 * @property offsetNs add it to the second recording's timestamps to put them on the first's clock.
 * @property correlation the normalised cross-correlation at that offset (1: the magnitudes match exactly).
 * @property runnerUp the best correlation at least [GyroAlignment.SEPARATION_NS] away from the peak:
 *   close to [correlation] means the motion repeats and the offset is ambiguous.
 * @property periodNs the fine grid's period, the resolution before the parabola.
 * @property overlapNs how long the two recordings overlap at that offset.
 * @property atSearchEdge the best lag lies at an end of the searched window, so the peak may lie
 *   beyond it: the offset is not a maximum of the correlation, only the window's best.
 */
public data class GyroAlignmentResult(
    val offsetNs: Long,
    val correlation: Double,
    val runnerUp: Double,
    val periodNs: Long,
    val overlapNs: Long,
    val atSearchEdge: Boolean = false,
)

public object GyroAlignment {
    /** The coarse grid's period: 20 Hz, fast enough for a shake's envelope. */
    public const val COARSE_NS: Long = 50_000_000

    /** How far from the peak a runner-up must be: half a second. */
    public const val SEPARATION_NS: Long = 500_000_000

    /**
     * The offset between two recordings' clocks from their angular-velocity magnitudes:
     * [aTimesNs]/[aRates] and [bTimesNs]/[bRates] (timestamps ns, increasing; |ω| rad/s), searched
     * within [expectedNs] ± [maxLagNs] and where they overlap by at least [minOverlapNs].
     * @throws IllegalArgumentException on arrays of different lengths, fewer than 3 samples, timestamps
     *   that do not increase, non-finite rates, or a search range with no such overlap.
     */
    public fun align(
        aTimesNs: LongArray,
        aRates: DoubleArray,
        bTimesNs: LongArray,
        bRates: DoubleArray,
        maxLagNs: Long = 60_000_000_000,
        expectedNs: Long = 0,
        minOverlapNs: Long = 5_000_000_000,
    ): GyroAlignmentResult {
        check(aTimesNs, aRates, "first")
        check(bTimesNs, bRates, "second")
        require(maxLagNs >= 0 && minOverlapNs > 0) { "maxLagNs must be ≥ 0 and minOverlapNs > 0" }
        val fine = minOf(medianPeriod(aTimesNs), medianPeriod(bTimesNs)).coerceAtLeast(1_000)
        val coarse = maxOf(COARSE_NS, fine)
        // The coarse search over the whole range.
        val best = search(aTimesNs, aRates, bTimesNs, bRates, coarse, expectedNs - maxLagNs, expectedNs + maxLagNs, minOverlapNs)
            ?: throw IllegalArgumentException("the recordings do not overlap by ${minOverlapNs / 1e9} s anywhere within ${expectedNs / 1e9} ± ${maxLagNs / 1e9} s")
        // The fine search around it, within the window, then the parabola (which stays within half a fine period).
        val from = maxOf(best.lag - 2 * coarse, expectedNs - maxLagNs)
        val to = minOf(best.lag + 2 * coarse, expectedNs + maxLagNs)
        val around = search(aTimesNs, aRates, bTimesNs, bRates, fine, from, to, minOverlapNs) ?: best
        val refined = around.refined.coerceIn(expectedNs - maxLagNs, expectedNs + maxLagNs)
        val edge = refined - (expectedNs - maxLagNs) < fine || (expectedNs + maxLagNs) - refined < fine
        return GyroAlignmentResult(refined, around.peak, best.runnerUp, fine, around.overlap, edge)
    }

    private class Found(val lag: Long, val peak: Double, val refined: Long, val runnerUp: Double, val overlap: Long)

    /** The best lag on a grid of [period] between [fromNs] and [toNs], or null when no lag overlaps enough. */
    private fun search(at: LongArray, ar: DoubleArray, bt: LongArray, br: DoubleArray, period: Long, fromNs: Long, toNs: Long, minOverlapNs: Long): Found? {
        val a = resample(at, ar, period)
        val b = resample(bt, br, period)
        // b's sample j at bt[0] + j·period lands at bt[0] + j·period + lag on a's clock = at[0] + i·period.
        val k0 = Math.floorDiv(fromNs + bt[0] - at[0], period)
        val k1 = Math.floorDiv(toNs + bt[0] - at[0] + period - 1, period)
        val minOverlap = (minOverlapNs / period).toInt().coerceAtLeast(3)
        val count = (k1 - k0 + 1).toInt()
        val corr = DoubleArray(count) { Double.NaN }
        var bestK = -1
        for (c in 0 until count) {
            val k = k0 + c
            val r = pearson(a, b, k, minOverlap)
            corr[c] = r
            if (!r.isNaN() && (bestK < 0 || r > corr[bestK])) bestK = c
        }
        if (bestK < 0) return null
        // A parabola through the peak and its neighbours, where both exist.
        var frac = 0.0
        if (bestK in 1 until count - 1 && !corr[bestK - 1].isNaN() && !corr[bestK + 1].isNaN()) {
            val l = corr[bestK - 1]
            val m = corr[bestK]
            val r = corr[bestK + 1]
            val d = l - 2 * m + r
            if (d < 0) frac = (0.5 * (l - r) / d).coerceIn(-0.5, 0.5)
        }
        val separation = (SEPARATION_NS / period).toInt()
        var runnerUp = Double.NEGATIVE_INFINITY
        for (c in 0 until count) if (Math.abs(c - bestK) >= separation && !corr[c].isNaN() && corr[c] > runnerUp) runnerUp = corr[c]
        val k = k0 + bestK
        val lag = at[0] - bt[0] + k * period
        val overlapSamples = minOf(a.size, b.size + k.toInt()) - maxOf(0, k.toInt())
        return Found(lag, corr[bestK], Math.round(lag + frac * period), if (runnerUp.isInfinite()) Double.NaN else runnerUp, overlapSamples * period)
    }

    /** Pearson's correlation of a[i] with b[i − k] over their overlap; NaN below [minOverlap] samples or without variation. */
    private fun pearson(a: DoubleArray, b: DoubleArray, k: Long, minOverlap: Int): Double {
        val from = maxOf(0L, k).toInt()
        val to = minOf(a.size.toLong(), b.size + k).toInt()
        val n = to - from
        if (n < minOverlap) return Double.NaN
        var sa = 0.0
        var sb = 0.0
        var saa = 0.0
        var sbb = 0.0
        var sab = 0.0
        val off = (-k).toInt()
        for (i in from until to) {
            val x = a[i]
            val y = b[i + off]
            sa += x
            sb += y
            saa += x * x
            sbb += y * y
            sab += x * y
        }
        val va = saa - sa * sa / n
        val vb = sbb - sb * sb / n
        if (va <= 0 || vb <= 0) return Double.NaN
        return (sab - sa * sb / n) / sqrt(va * vb)
    }

    /** The samples on a grid of [period] from the first timestamp: the mean of the samples in each cell, linear across empty cells. */
    private fun resample(t: LongArray, v: DoubleArray, period: Long): DoubleArray {
        val n = ((t.last() - t[0]) / period + 1).toInt()
        val sum = DoubleArray(n)
        val count = IntArray(n)
        for (i in t.indices) {
            val c = ((t[i] - t[0] + period / 2) / period).toInt().coerceAtMost(n - 1)
            sum[c] += v[i]
            count[c]++
        }
        val out = DoubleArray(n)
        var last = -1
        for (c in 0 until n) {
            if (count[c] == 0) continue
            out[c] = sum[c] / count[c]
            if (last >= 0 && c - last > 1) {
                for (g in last + 1 until c) out[g] = out[last] + (out[c] - out[last]) * (g - last) / (c - last)
            }
            last = c
        }
        return out
    }

    private fun medianPeriod(t: LongArray): Long {
        val d = LongArray(t.size - 1) { t[it + 1] - t[it] }
        d.sort()
        return d[d.size / 2]
    }

    private fun check(t: LongArray, v: DoubleArray, which: String) {
        require(t.size == v.size) { "the $which recording has ${t.size} timestamps and ${v.size} rates" }
        require(t.size >= 3) { "the $which recording has fewer than 3 gyroscope samples" }
        for (i in 1 until t.size) require(t[i] > t[i - 1]) { "the $which recording's timestamps do not increase at sample $i" }
        for (i in v.indices) require(v[i].isFinite()) { "the $which recording's rate at sample $i is not finite" }
    }
}
