/*
 * Comparison of the replayed orientation with a reference orientation (the phone's rotation
 * vector, or ground truth) over time, with BROAD's error decomposition (Orientations.splitError,
 * as core eval's BroadMetric): total, heading (about the vertical) and inclination, degrees.
 *
 * Each reference sample is compared at its own timestamp with the estimate interpolated (slerp)
 * between the gyroscope steps around it, so different sampling rates add no lag error.
 */
package dev.motionfusion.core.replay

import dev.motionfusion.core.Orientations
import kotlin.math.min
import kotlin.math.sqrt

/**
 * Streams estimates and reference samples; calls [onError] with (timestampNs, total, heading,
 * inclination in degrees) for each reference sample that lies between two estimates at most
 * [maxGapNs] apart. With [removeInitialHeadingOffset] (references with arbitrary yaw, e.g. the game
 * rotation vector) the heading difference of the first compared sample is removed from all.
 */
public class OrientationComparison(
    private val removeInitialHeadingOffset: Boolean = false,
    private val maxGapNs: Long = 500_000_000L,
    private val onError: (Long, Double, Double, Double) -> Unit,
) {
    private val pendingT = LongArray(PENDING)
    private val pendingQ = Array(PENDING) { DoubleArray(4) }
    private var pendingCount = 0
    private var hasPrev = false
    private var prevT = 0L
    private val prevQ = DoubleArray(4)
    private val interp = DoubleArray(4)
    private val e = DoubleArray(4)
    private val split = DoubleArray(3)
    private var headingOffset = 0.0
    private var offsetKnown = !removeInitialHeadingOffset

    /** Running statistics of the total error, degrees. */
    public val total: ErrorStatistics = ErrorStatistics()
    public val heading: ErrorStatistics = ErrorStatistics()
    public val inclination: ErrorStatistics = ErrorStatistics()

    /** An estimate (unit quaternion, sensor → ENU; NaN when not yet known) at [tNs]. */
    public fun estimate(tNs: Long, q: DoubleArray) {
        if (!q[0].isFinite()) return
        if (hasPrev && pendingCount > 0) {
            val dt = tNs - prevT
            for (i in 0 until pendingCount) {
                val tr = pendingT[i]
                if (dt in 1..maxGapNs && tr >= prevT && tr <= tNs) {
                    Orientations.slerp(prevQ, q, (tr - prevT).toDouble() / dt, interp)
                    compare(tr, interp, pendingQ[i])
                } else if (tr == tNs) {
                    compare(tr, q, pendingQ[i])
                }
            }
        } else if (pendingCount > 0) {
            for (i in 0 until pendingCount) if (pendingT[i] == tNs) compare(tNs, q, pendingQ[i])
        }
        pendingCount = 0
        hasPrev = true
        prevT = tNs
        q.copyInto(prevQ, 0, 0, 4)
    }

    /** A reference sample (unit quaternion [w, x, y, z], sensor → ENU) at [tNs]. */
    public fun reference(tNs: Long, w: Double, x: Double, y: Double, z: Double) {
        if (!(w.isFinite() && x.isFinite() && y.isFinite() && z.isFinite())) return
        val n = sqrt(w * w + x * x + y * y + z * z)
        if (n < 1e-6) return
        if (hasPrev && tNs < prevT) return // older than the latest estimate: out of order
        if (pendingCount == PENDING) pendingCount-- // more references than estimates: keep the newest
        pendingT[pendingCount] = tNs
        val p = pendingQ[pendingCount]
        p[0] = w / n; p[1] = x / n; p[2] = y / n; p[3] = z / n
        pendingCount++
    }

    private fun compare(t: Long, q: DoubleArray, r: DoubleArray) {
        Orientations.errorQuaternion(q, r, e)
        if (!offsetKnown) {
            headingOffset = Orientations.signedHeading(e)
            offsetKnown = true
        }
        if (headingOffset != 0.0) Orientations.removeHeading(e, headingOffset)
        Orientations.splitError(e, split, 0)
        val totalDeg = split[0] * DEG
        val headingDeg = split[1] * DEG
        val inclinationDeg = split[2] * DEG
        total.add(totalDeg)
        heading.add(headingDeg)
        inclination.add(inclinationDeg)
        onError(t, totalDeg, headingDeg, inclinationDeg)
    }

    private companion object {
        const val PENDING = 64
        const val DEG = 180.0 / Math.PI
    }
}

/**
 * Running statistics of non-negative errors in degrees, constant memory: count, mean, RMS, max,
 * and percentiles from a histogram of 0.01° bins up to 180°.
 */
public class ErrorStatistics {
    private val bins = LongArray(BINS + 1)
    private var sum = 0.0
    private var sumSq = 0.0

    public var count: Long = 0L
        private set
    public var max: Double = Double.NaN
        private set

    public fun add(v: Double) {
        if (!v.isFinite()) return
        count++
        sum += v
        sumSq += v * v
        if (!(v <= max)) max = v
        bins[min(BINS, (v / BIN_DEG).toInt().coerceAtLeast(0))]++
    }

    public val mean: Double get() = if (count > 0) sum / count else Double.NaN
    public val rms: Double get() = if (count > 0) sqrt(sumSq / count) else Double.NaN

    /** The [p]-quantile (0..1), to 0.01°. */
    public fun percentile(p: Double): Double {
        if (count == 0L) return Double.NaN
        val rank = kotlin.math.ceil(p * count).toLong().coerceIn(1, count)
        var seen = 0L
        for (i in bins.indices) {
            seen += bins[i]
            if (seen >= rank) return min((i + 0.5) * BIN_DEG, max)
        }
        return max
    }

    private companion object {
        const val BIN_DEG = 0.01
        const val BINS = 18_000
    }
}
