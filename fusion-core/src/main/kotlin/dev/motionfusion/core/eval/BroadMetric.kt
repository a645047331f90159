/*
 * BROAD's error metric (Laidig et al., "BROAD—A Benchmark for Robust Inertial Orientation
 * Estimation", Data 6(7):72, 2021), as stated in the subset README.
 *
 * Both orientations are sensor → earth quaternions [w, x, y, z] (Hamilton) in the same earth frame
 * (ENU for BROAD). Error e = q_est ⊗ q_truth*, an earth-frame rotation: total error 2·acos|e_w|,
 * heading error 2·atan|e_z / e_w| (about the vertical), inclination error 2·acos √(e_w² + e_z²).
 * Each is an RMSE in degrees over the scored samples, skipping samples without truth.
 */
package dev.motionfusion.core.eval

import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.atan
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.min
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
    public class HeadingOffset {
        private val e = DoubleArray(4)
        private var s = 0.0
        private var c = 0.0

        public fun add(estimate: DoubleArray, truth: DoubleArray, scored: Boolean) {
            if (!errorQuaternion(estimate, truth, scored, e)) return
            val psi = 2.0 * atan2(e[3], e[0])
            s += sin(psi)
            c += cos(psi)
        }

        /** The offset, rad (0 before any sample). */
        public val offsetRad: Double get() = atan2(s, c)
    }

    /** Streams samples into the three RMSEs, with a constant heading offset [headingOffsetRad] removed first. */
    public class Accumulator(headingOffsetRad: Double = 0.0) {
        // Pre-multiplying by a rotation of −offset about z removes it: [cos(−o/2), 0, 0, sin(−o/2)].
        private val cw = cos(0.5 * headingOffsetRad)
        private val cz = -sin(0.5 * headingOffsetRad)
        private val e = DoubleArray(4)
        private var total = 0.0
        private var heading = 0.0
        private var incl = 0.0
        private var count = 0

        public fun add(estimate: DoubleArray, truth: DoubleArray, scored: Boolean) {
            if (!errorQuaternion(estimate, truth, scored, e)) return
            val w = cw * e[0] - cz * e[3]
            val x = cw * e[1] - cz * e[2]
            val y = cw * e[2] + cz * e[1]
            val z = cw * e[3] + cz * e[0]
            val norm = sqrt(w * w + x * x + y * y + z * z)
            val aw = abs(w) / norm
            val az = z / norm
            val t = 2.0 * acos(min(1.0, aw))
            val h = 2.0 * atan(abs(az / aw))
            val inc = 2.0 * acos(min(1.0, sqrt(aw * aw + az * az)))
            total += t * t
            heading += h * h
            incl += inc * inc
            count++
        }

        public fun result(): ErrorRmse {
            val deg = 180.0 / Math.PI
            return ErrorRmse(sqrt(total / count) * deg, sqrt(heading / count) * deg, sqrt(incl / count) * deg, count)
        }
    }

    /** e = q ⊗ p* into [e]; false when the sample is not scored or either quaternion is not finite. */
    private fun errorQuaternion(q: DoubleArray, p: DoubleArray, scored: Boolean, e: DoubleArray): Boolean {
        if (!scored) return false
        for (k in 0 until 4) if (!q[k].isFinite() || !p[k].isFinite()) return false
        // Hamilton product of q with p* = [pw, −px, −py, −pz].
        e[0] = q[0] * p[0] + q[1] * p[1] + q[2] * p[2] + q[3] * p[3]
        e[1] = -q[0] * p[1] + q[1] * p[0] - q[2] * p[3] + q[3] * p[2]
        e[2] = -q[0] * p[2] + q[1] * p[3] + q[2] * p[0] - q[3] * p[1]
        e[3] = -q[0] * p[3] - q[1] * p[2] + q[2] * p[1] + q[3] * p[0]
        return true
    }
}
