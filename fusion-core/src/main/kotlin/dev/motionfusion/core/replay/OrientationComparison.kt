/*
 * Comparison of the replayed orientation with a reference orientation (the phone's rotation
 * vector, or ground truth) over time, with BROAD's error decomposition (core eval's BroadMetric):
 * e = q_est ⊗ q_ref* (an earth-frame rotation, ENU); total 2·atan2(|e_xyz|, |e_w|), heading
 * (about the vertical) 2·atan|e_z / e_w|, inclination 2·acos √(e_w² + e_z²), degrees.
 *
 * Each reference sample is compared at its own timestamp with the estimate interpolated (slerp)
 * between the gyroscope steps around it, so different sampling rates add no lag error.
 */
package dev.motionfusion.core.replay

import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.atan
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.min
import kotlin.math.sin
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
    private var offsetW = 1.0
    private var offsetZ = 0.0
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
                    slerp(prevQ, q, (tr - prevT).toDouble() / dt, interp)
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
        // e = q ⊗ r*
        var ew = q[0] * r[0] + q[1] * r[1] + q[2] * r[2] + q[3] * r[3]
        var ex = -q[0] * r[1] + q[1] * r[0] - q[2] * r[3] + q[3] * r[2]
        var ey = -q[0] * r[2] + q[1] * r[3] + q[2] * r[0] - q[3] * r[1]
        var ez = -q[0] * r[3] - q[1] * r[2] + q[2] * r[1] + q[3] * r[0]
        if (!offsetKnown) {
            val psi = 2.0 * atan2(ez, ew)
            offsetW = cos(0.5 * psi)
            offsetZ = -sin(0.5 * psi)
            offsetKnown = true
        }
        if (offsetZ != 0.0) {
            // Rz(−ψ) ⊗ e
            val w = offsetW * ew - offsetZ * ez
            val x = offsetW * ex - offsetZ * ey
            val y = offsetW * ey + offsetZ * ex
            val z = offsetW * ez + offsetZ * ew
            ew = w; ex = x; ey = y; ez = z
        }
        val n = sqrt(ew * ew + ex * ex + ey * ey + ez * ez)
        val aw = abs(ew) / n
        val az = ez / n
        val totalDeg = 2.0 * atan2(sqrt(ex * ex + ey * ey + ez * ez) / n, aw) * DEG
        val headingDeg = 2.0 * atan(abs(az / aw)) * DEG
        val inclinationDeg = 2.0 * acos(min(1.0, sqrt(aw * aw + az * az))) * DEG
        total.add(totalDeg)
        heading.add(headingDeg)
        inclination.add(inclinationDeg)
        onError(t, totalDeg, headingDeg, inclinationDeg)
    }

    public companion object {
        private const val PENDING = 64
        private const val DEG = 180.0 / Math.PI

        /** Spherical interpolation of unit quaternions along the shorter arc into [out]. */
        internal fun slerp(a: DoubleArray, b: DoubleArray, t: Double, out: DoubleArray) {
            var d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
            val sign = if (d < 0) -1.0 else 1.0
            d *= sign
            val s0: Double
            val s1: Double
            if (d > 0.9995) {
                s0 = 1.0 - t
                s1 = t * sign
            } else {
                val theta = acos(min(d, 1.0))
                val st = sin(theta)
                s0 = sin((1.0 - t) * theta) / st
                s1 = sin(t * theta) / st * sign
            }
            var n = 0.0
            for (k in 0 until 4) {
                out[k] = s0 * a[k] + s1 * b[k]
                n += out[k] * out[k]
            }
            n = 1.0 / sqrt(n)
            for (k in 0 until 4) out[k] *= n
        }
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
