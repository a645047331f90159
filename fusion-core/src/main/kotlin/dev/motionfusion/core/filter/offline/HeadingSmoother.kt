/*
 * The offline estimate's heading smoother (a Kalman filter and a Rauch–Tung–Striebel pass on the heading
 * correction and the residual vertical gyroscope bias), its state kept per record in the spill file.
 * Orientations sensor → ENU, [w, x, y, z]; rad, rad/s, s.
 */
package dev.motionfusion.core.filter.offline

import dev.motionfusion.core.filter.SensorRanges
import dev.motionfusion.core.unitQuaternionToMatrix
import java.nio.ByteBuffer
import kotlin.math.PI
import kotlin.math.atan
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.sin

/**
 * The heading smoother of the offline estimate: a Kalman filter over the whole recording, then a
 * Rauch–Tung–Striebel pass back over it, on two numbers: x, the heading correction (rad, a turn about
 * the world's vertical applied on the left) of the backward pass's orientation, and b, what is left of
 * the gyroscope's bias about the vertical (rad/s) after the filter's own estimate. From one step to the
 * next x changes by u − b·Δt, u the heading correction the backward pass's own step made (−1 × the turn
 * about the vertical between its new orientation and where the gyroscope alone would have taken it),
 * so x follows the gyroscope, and b lets the gyroscope drift steadily between two stretches where the
 * magnetometer is trusted. Each fresh magnetometer reading measures x (the turn that brings its
 * horizontal part onto north) with a variance of [OfflineSettings.smootherRestNoise]² / Δt at rest (the
 * rest detector's flag, where the field holds steady in motion: [OfflineSettings.smootherRestSpread]) and
 * [OfflineSettings.smootherMotionNoise]² / Δt in motion; a reading the field check finds disturbed
 * ([FieldReference]) is left out, and with the magnetic trust on (FilterSettings.magTrustSpread) a reading's
 * variance is divided by r³, r the backward pass's trust at that step. So where a recording rests, the heading is pinned there and the
 * gyroscope's drift between rests is taken out, and the magnetometer in motion, which the rest of the
 * estimate follows, counts little.
 *
 * The filter runs in the backward pass (its own time order, the recording's backward) and keeps each
 * record's filtered state (x, b and their covariance, and u) in the spill file; the smoothing runs in the
 * second forward pass from that. State: a few doubles, whatever the length. Across a gap the filter starts
 * again (the backward pass took another orientation there).
 */
internal class HeadingSmoother(s: OfflineSettings) {
    private val rRest = s.smootherRestNoise * s.smootherRestNoise
    private val rMotion = s.smootherMotionNoise * s.smootherMotionNoise
    private val qx = s.smootherHeadingNoise * s.smootherHeadingNoise
    private val qb = s.smootherBiasNoise * s.smootherBiasNoise
    private var x = 0.0
    private var b = 0.0
    private var p11 = 0.0
    private var p12 = 0.0
    private var p22 = 0.0
    private var started = false
    private val prev = DoubleArray(4)

    // The smoothing pass: the previous record's smoothed state and its increment.
    private var xs = Double.NaN
    private var bs = 0.0
    private var prevU = Double.NaN
    private var prevNs = 0L

    private fun start() {
        x = 0.0; b = 0.0
        p11 = X0 * X0; p12 = 0.0; p22 = B0 * B0
        started = true
    }

    /** One step of the filter at the record at [at]: orientation [q], rate (bias-corrected) of the step into it; [trust] the pass's magnetic trust, 0…1. */
    fun filterStep(buf: ByteBuffer, at: Int, q: DoubleArray, linked: Boolean, wx: Double, wy: Double, wz: Double, dt: Double,
                   magFresh: Boolean, m: DoubleArray, rest: Boolean, disturbed: Boolean, trust: Double) {
        var u = Double.NaN
        if (q[0].isNaN()) {
            started = false
        } else {
            if (!started || !linked) {
                start()
            } else {
                u = correction(prev, q, wx, wy, wz, dt)
                // A reading the filter skipped (not finite): the step's turn is unknown, so x carries on unchanged
                // and only its uncertainty grows; a NaN here would otherwise stay in x to the start of the pass.
                if (!u.isFinite()) u = 0.0
                x += u - b * dt
                val n11 = p11 - 2.0 * dt * p12 + dt * dt * p22 + qx * dt
                val n12 = p12 - dt * p22
                p22 += qb * dt
                p11 = n11; p12 = n12
            }
            if (magFresh && dt > 0.0 && !disturbed && usable(m)) {
                // The reading's measure of x, its variance, and the update (P ← (I − K H) P, H = [1, 0]).
                // Its variance grows as the pass's magnetic trust r falls (MagneticTrust: 1 without it) by 1/r³,
                // as the causal filter's bias estimate weighs it: from these readings the smoother learns a bias too.
                var r = (if (rest) rRest else rMotion) / dt
                if (trust < 1.0) r /= trust * trust * trust
                val e = wrap(magHeading(m, q) - x)
                val sInv = 1.0 / (p11 + r)
                val k1 = p11 * sInv
                val k2 = p12 * sInv
                x += k1 * e; b += k2 * e
                p22 -= k2 * p12
                p11 *= 1.0 - k1
                p12 *= 1.0 - k1
            }
            q.copyInto(prev)
        }
        buf.putDouble(at + Spill.KX, if (started) x else Double.NaN)
        buf.putDouble(at + Spill.KB, b)
        buf.putDouble(at + Spill.KP11, p11)
        buf.putDouble(at + Spill.KP12, p12)
        buf.putDouble(at + Spill.KP22, p22)
        buf.putDouble(at + Spill.KU, u)
    }

    /** The smoothed correction at the record at [at] (time [ns]) applied to [q] (the backward pass's orientation); false where there is none. */
    fun smoothStep(buf: ByteBuffer, at: Int, ns: Long, q: DoubleArray): Boolean {
        val xk = buf.getDouble(at + Spill.KX)
        val u = buf.getDouble(at + Spill.KU)
        if (xk.isNaN()) {
            xs = Double.NaN
            prevU = u
            prevNs = ns
            return false
        }
        val bk = buf.getDouble(at + Spill.KB)
        if (xs.isNaN() || prevU.isNaN()) {
            xs = xk; bs = bk
        } else {
            val a11 = buf.getDouble(at + Spill.KP11)
            val a12 = buf.getDouble(at + Spill.KP12)
            val a22 = buf.getDouble(at + Spill.KP22)
            val dt = (ns - prevNs) * 1e-9
            // The prediction from this record to the previous one (the filter's order), and the gain.
            val xp = xk + prevU - bk * dt
            val pp11 = a11 - 2.0 * dt * a12 + dt * dt * a22 + qx * dt
            val pp12 = a12 - dt * a22
            val pp22 = a22 + qb * dt
            // P F^T
            val f11 = a11 - dt * a12
            val f12 = a12
            val f21 = a12 - dt * a22
            val f22 = a22
            val det = pp11 * pp22 - pp12 * pp12
            val i11 = pp22 / det
            val i12 = -pp12 / det
            val i22 = pp11 / det
            val c11 = f11 * i11 + f12 * i12
            val c12 = f11 * i12 + f12 * i22
            val c21 = f21 * i11 + f22 * i12
            val c22 = f21 * i12 + f22 * i22
            val dx = wrap(xs - xp)
            val db = bs - bk
            xs = xk + c11 * dx + c12 * db
            bs = bk + c21 * dx + c22 * db
        }
        prevU = u
        prevNs = ns
        // q ← Rz(xs) ⊗ q
        val c = cos(0.5 * xs)
        val s = sin(0.5 * xs)
        val q0 = c * q[0] - s * q[3]
        val q1 = c * q[1] - s * q[2]
        val q2 = c * q[2] + s * q[1]
        val q3 = c * q[3] + s * q[0]
        q[0] = q0; q[1] = q1; q[2] = q2; q[3] = q3
        return true
    }

    companion object {
        /** The filter's start: x and b unknown within 5° and 0.2°/s (a standard deviation). */
        const val X0 = 5.0 * PI / 180.0
        const val B0 = 0.2 * PI / 180.0

        /**
         * The heading correction (rad, about the world's vertical) between [q] and where the rate ([wx], [wy], [wz],
         * rad/s) over [dt] s would have taken [prev] alone: −1 × the turn of c = q ⊗ p* about the vertical, p the
         * gyroscope's prediction. NaN where a reading was not finite.
         */
        fun correction(prev: DoubleArray, q: DoubleArray, wx: Double, wy: Double, wz: Double, dt: Double): Double {
            val h = 0.5 * dt
            val p0 = prev[0] + h * (-prev[1] * wx - prev[2] * wy - prev[3] * wz)
            val p1 = prev[1] + h * (prev[0] * wx + prev[2] * wz - prev[3] * wy)
            val p2 = prev[2] + h * (prev[0] * wy - prev[1] * wz + prev[3] * wx)
            val p3 = prev[3] + h * (prev[0] * wz + prev[1] * wy - prev[2] * wx)
            val cw = q[0] * p0 + q[1] * p1 + q[2] * p2 + q[3] * p3
            val cz = -q[0] * p3 - q[1] * p2 + q[2] * p1 + q[3] * p0
            return -2.0 * atan(cz / cw)
        }

        fun wrap(a: Double): Double = if (a > PI) a - 2 * PI else if (a < -PI) a + 2 * PI else a

        /** A magnetometer reading that can measure the heading: finite, not zero (an empty field of a table is NaN), no stronger than the earth's. */
        fun usable(m: DoubleArray): Boolean = SensorRanges.isEarthField(m[0], m[1], m[2])

        /** The correction about the vertical (rad) that turns [q] (sensor → ENU) so that the field [m] points north. */
        fun magHeading(m: DoubleArray, q: DoubleArray): Double {
            return unitQuaternionToMatrix(q, 0) { r00, r01, r02, r10, r11, r12, _, _, _ ->
                atan2(r00 * m[0] + r01 * m[1] + r02 * m[2], r10 * m[0] + r11 * m[1] + r12 * m[2])
            }
        }
    }
}
