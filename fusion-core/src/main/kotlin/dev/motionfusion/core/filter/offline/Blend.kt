/*
 * The offline estimate's blend of two passes: heading and inclination weighed apart, the heading by how
 * recently each pass met a disturbed field. Quaternions [w, x, y, z], unit, sensor → world (ENU).
 */
package dev.motionfusion.core.filter.offline

import kotlin.math.sqrt

internal object Blend {
    /**
     * The backward pass's weight in the heading, from [w0] (its weight where neither pass has met a
     * disturbed field lately) and how recently each pass met one ([forward], [backward]: 1 just then,
     * towards 0 as the heading correction has pulled the error out): each pass's confidence, (1 − w0) or
     * w0, shrinks by that factor (down to a floor), and the weight is the backward one's share.
     */
    fun headingWeight(w0: Double, forward: Double, backward: Double): Double {
        val f = (1.0 - w0) * (1.0 - forward) + CONFIDENCE_FLOOR
        val b = w0 * (1.0 - backward) + CONFIDENCE_FLOOR
        return b / (f + b)
    }

    /** The least confidence a pass keeps, so that where both met a disturbance lately the weights stay defined. */
    const val CONFIDENCE_FLOOR = 0.05

    /**
     * p ← p turned towards q (unit quaternions, sensor → world) by the fraction [wh] of the rotation
     * between them about the world's vertical (heading) and by [wi] of the rotation about the horizontal
     * axes (inclination): with e = q ⊗ p* (the sign taken with e_w ≥ 0), e' = [e_w, wi·e_x, wi·e_y, wh·e_z]
     * normalised, p ← e' ⊗ p. For wh = wi = w the result lies on the arc from p to q, at tan(θ'/2) =
     * w·tan(θ/2) for the angle θ between them (for estimates a few degrees apart slerp by w to within
     * 10⁻³ of θ). Where one is NaN, the other.
     */
    fun combine(p: DoubleArray, q: DoubleArray, wh: Double, wi: Double) {
        if (q[0].isNaN()) return
        if (p[0].isNaN()) {
            q.copyInto(p)
            return
        }
        val p0 = p[0]
        val p1 = p[1]
        val p2 = p[2]
        val p3 = p[3]
        var e0 = q[0] * p0 + q[1] * p1 + q[2] * p2 + q[3] * p3
        var e1 = -q[0] * p1 + q[1] * p0 - q[2] * p3 + q[3] * p2
        var e2 = -q[0] * p2 + q[1] * p3 + q[2] * p0 - q[3] * p1
        var e3 = -q[0] * p3 - q[1] * p2 + q[2] * p1 + q[3] * p0
        if (e0 < 0.0) {
            e0 = -e0; e1 = -e1; e2 = -e2; e3 = -e3
        }
        e1 *= wi; e2 *= wi; e3 *= wh
        val r0 = e0 * p0 - e1 * p1 - e2 * p2 - e3 * p3
        val r1 = e0 * p1 + e1 * p0 + e2 * p3 - e3 * p2
        val r2 = e0 * p2 - e1 * p3 + e2 * p0 + e3 * p1
        val r3 = e0 * p3 + e1 * p2 - e2 * p1 + e3 * p0
        val inv = 1.0 / sqrt(r0 * r0 + r1 * r1 + r2 * r2 + r3 * r3)
        p[0] = r0 * inv; p[1] = r1 * inv; p[2] = r2 * inv; p[3] = r3 * inv
    }
}
