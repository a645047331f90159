/*
 * BROAD's error metric (Laidig et al., "BROAD—A Benchmark for Robust Inertial Orientation
 * Estimation", Data 6(7):72, 2021), as stated in the subset README.
 *
 * Both orientations are sensor → earth quaternions [w, x, y, z] (Hamilton) in the same earth frame
 * (ENU for BROAD). Error e = q_est ⊗ q_truth*, an earth-frame rotation: total error 2·acos|e_w|,
 * heading error 2·atan|e_z / e_w| (about the vertical), inclination error 2·acos √(e_w² + e_z²)
 * (computed by core's Orientations.splitError, the total as the stable 2·atan2(|e_xyz|, |e_w|)).
 * Each is an RMSE in degrees over the scored samples, skipping samples without truth.
 */
package dev.motionfusion.core.eval

import dev.motionfusion.core.Orientations
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.sin
import kotlin.math.sqrt

/** RMSE of the three BROAD errors, degrees, over [samples] scored samples. */
public data class ErrorRmse(val totalDeg: Double, val headingDeg: Double, val inclinationDeg: Double, val samples: Int)

public object BroadMetric {
    /**
     * RMSE of [estimate] against [truth] (rows [w, x, y, z], same earth frame) over the samples where
     * [scored] is true and both are finite. With [removeHeadingOffset] (6D filters), one constant
     * rotation about the vertical, the circular mean of the signed heading errors, is removed first.
     */
    public fun rmse(estimate: Array<DoubleArray>, truth: Array<DoubleArray>, scored: BooleanArray, removeHeadingOffset: Boolean): ErrorRmse {
        val n = estimate.size
        require(truth.size == n && scored.size == n) { "length mismatch" }
        var offset = 0.0
        if (removeHeadingOffset) {
            val h = HeadingOffset()
            for (i in 0 until n) h.add(estimate[i], truth[i], scored[i])
            offset = h.offsetRad
        }
        val acc = Accumulator(offset)
        for (i in 0 until n) acc.add(estimate[i], truth[i], scored[i])
        return acc.result()
    }

    /**
     * The RMSEs of samples streamed by [pass], which calls its argument with (estimate, truth,
     * scored) for each sample and may be called twice: with [removeHeadingOffset] a first pass
     * finds the offset. Memory does not grow with the number of samples.
     */
    public fun streamed(removeHeadingOffset: Boolean, pass: (add: (DoubleArray, DoubleArray, Boolean) -> Unit) -> Unit): ErrorRmse {
        var offset = 0.0
        if (removeHeadingOffset) {
            val h = HeadingOffset()
            pass(h::add)
            offset = h.offsetRad
        }
        val acc = Accumulator(offset)
        pass(acc::add)
        return acc.result()
    }

    /** The circular mean of the signed heading errors of the samples [add]ed (first pass of a 6D score). */
    internal class HeadingOffset {
        private val e = DoubleArray(4)
        private var s = 0.0
        private var c = 0.0

        fun add(estimate: DoubleArray, truth: DoubleArray, scored: Boolean) {
            if (!errorQuaternion(estimate, truth, scored, e)) return
            val psi = Orientations.signedHeading(e)
            s += sin(psi)
            c += cos(psi)
        }

        /** The offset, rad (0 before any sample). */
        val offsetRad: Double get() = atan2(s, c)
    }

    /** Streams samples into the three RMSEs, with a constant heading offset [headingOffsetRad] removed first. */
    internal class Accumulator(private val headingOffsetRad: Double = 0.0) {
        private val e = DoubleArray(4)
        private val split = DoubleArray(3)
        private var total = 0.0
        private var heading = 0.0
        private var incl = 0.0
        private var count = 0

        fun add(estimate: DoubleArray, truth: DoubleArray, scored: Boolean) {
            if (!errorQuaternion(estimate, truth, scored, e)) return
            if (headingOffsetRad != 0.0) Orientations.removeHeading(e, headingOffsetRad)
            Orientations.splitError(e, split, 0)
            total += split[0] * split[0]
            heading += split[1] * split[1]
            incl += split[2] * split[2]
            count++
        }

        fun result(): ErrorRmse {
            val deg = 180.0 / Math.PI
            return ErrorRmse(sqrt(total / count) * deg, sqrt(heading / count) * deg, sqrt(incl / count) * deg, count)
        }
    }

    /** e = q ⊗ p* into [e]; false when the sample is not scored or either quaternion is not finite. */
    private fun errorQuaternion(q: DoubleArray, p: DoubleArray, scored: Boolean, e: DoubleArray): Boolean {
        if (!scored) return false
        for (k in 0 until 4) if (!q[k].isFinite() || !p[k].isFinite()) return false
        Orientations.errorQuaternion(q, p, e)
        return true
    }
}
