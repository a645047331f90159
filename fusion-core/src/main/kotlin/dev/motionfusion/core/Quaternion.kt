/*
 * Quaternion: an immutable quaternion, order [w, x, y, z] (scalar first), Hamilton product
 * (i² = j² = k² = ijk = −1).
 *
 * A unit quaternion q used as an orientation maps sensor-frame vectors into the world frame:
 *     v_world = q ⊗ [0, v_sensor] ⊗ q*
 * so its rotation matrix R(q) satisfies v_world = R · v_sensor (the same direction as the
 * matrix of Android's getRotationMatrix). Which world (ENU, NWU, NED) is stated by whoever
 * produces it; see docs/CONVENTIONS.md.
 */
package dev.motionfusion.core

import kotlin.math.abs
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.sin
import kotlin.math.sqrt

/** An immutable quaternion [w, x, y, z], Hamilton convention. */
public data class Quaternion(val w: Double, val x: Double, val y: Double, val z: Double) {

    /**
     * This ⊗ (w, x, y, z) written to out[at..at+3] as [w, x, y, z], allocating nothing: the frame
     * change of an orientation on a hot path (q_to = c ⊗ q_from, c from [WorldFrame.quaternionTo]).
     */
    internal fun timesInto(w: Double, x: Double, y: Double, z: Double, out: DoubleArray, at: Int) {
        out[at] = this.w * w - this.x * x - this.y * y - this.z * z
        out[at + 1] = this.w * x + this.x * w + this.y * z - this.z * y
        out[at + 2] = this.w * y - this.x * z + this.y * w + this.z * x
        out[at + 3] = this.w * z + this.x * y - this.y * x + this.z * w
    }

    /** Hamilton product this ⊗ o. */
    public operator fun times(o: Quaternion): Quaternion = Quaternion(
        w * o.w - x * o.x - y * o.y - z * o.z,
        w * o.x + x * o.w + y * o.z - z * o.y,
        w * o.y - x * o.z + y * o.w + z * o.x,
        w * o.z + x * o.y - y * o.x + z * o.w,
    )

    /** Every component scaled by [s] (not a rotation unless renormalised). */
    public operator fun times(s: Double): Quaternion = Quaternion(w * s, x * s, y * s, z * s)

    /** Componentwise sum (used by integration and interpolation). */
    public operator fun plus(o: Quaternion): Quaternion = Quaternion(w + o.w, x + o.x, y + o.y, z + o.z)

    /** Componentwise difference. */
    public operator fun minus(o: Quaternion): Quaternion = Quaternion(w - o.w, x - o.x, y - o.y, z - o.z)

    /** −q: the same rotation as q. */
    public operator fun unaryMinus(): Quaternion = Quaternion(-w, -x, -y, -z)

    /** q* = [w, −x, −y, −z]: the inverse rotation of a unit quaternion (world → sensor for an orientation). */
    public fun conjugate(): Quaternion = Quaternion(w, -x, -y, -z)

    /** |q|². */
    public fun normSquared(): Double = w * w + x * x + y * y + z * z

    /** |q|, 1 for a rotation. */
    public fun norm(): Double = sqrt(normSquared())

    /** 4-D dot product; |q·o| = cos(half the angle between the rotations) for unit quaternions. */
    public fun dot(o: Quaternion): Double = w * o.w + x * o.x + y * o.y + z * o.z

    public fun isFinite(): Boolean = w.isFinite() && x.isFinite() && y.isFinite() && z.isFinite()

    /**
     * Multiplicative inverse q* / |q|².
     * @throws IllegalArgumentException for the zero quaternion.
     */
    public fun inverse(): Quaternion {
        val n2 = normSquared()
        require(n2 > 0.0 && n2.isFinite()) { "cannot invert $this" }
        return Quaternion(w / n2, -x / n2, -y / n2, -z / n2)
    }

    /**
     * This quaternion scaled to unit norm.
     * @throws IllegalArgumentException for a zero or non-finite quaternion.
     */
    public fun normalized(): Quaternion {
        val n = norm()
        require(n > 0.0 && n.isFinite()) { "cannot normalise $this" }
        return Quaternion(w / n, x / n, y / n, z / n)
    }

    /** The same rotation with w ≥ 0 (q and −q are the same rotation). */
    public fun canonical(): Quaternion = if (w < 0.0) -this else this

    /** The vector part [x, y, z]. */
    public fun vector(): Vector3 = Vector3(x, y, z)

    /**
     * Rotates [v] by this unit quaternion: q ⊗ [0, v] ⊗ q*. For an orientation (sensor → world)
     * this takes a sensor-frame vector into the world frame. Assumes |q| = 1.
     */
    public fun rotate(v: Vector3): Vector3 {
        // t = 2 (q_v × v); v' = v + w t + q_v × t  (expanded q v q*, valid for unit q)
        val tx = 2.0 * (y * v.z - z * v.y)
        val ty = 2.0 * (z * v.x - x * v.z)
        val tz = 2.0 * (x * v.y - y * v.x)
        return Vector3(
            v.x + w * tx + (y * tz - z * ty),
            v.y + w * ty + (z * tx - x * tz),
            v.z + w * tz + (x * ty - y * tx),
        )
    }

    /** Rotates [v] by the inverse of this unit quaternion: q* ⊗ [0, v] ⊗ q (world → sensor for an orientation). */
    public fun inverseRotate(v: Vector3): Vector3 = conjugate().rotate(v)

    /**
     * The angle in radians, in [0, π], of the rotation that takes this orientation to [o]
     * (2·acos|⟨q, o⟩| computed stably). Both must be unit quaternions.
     */
    public fun angleTo(o: Quaternion): Double {
        // 2·atan2(|vec(e)|, |w(e)|) with e = this* ⊗ o is stable near 0 and π.
        val e = conjugate() * o
        val vn = sqrt(e.x * e.x + e.y * e.y + e.z * e.z)
        return 2.0 * atan2(vn, abs(e.w))
    }

    /** Rotation angle of this unit quaternion, in [0, π]. */
    public fun angle(): Double = 2.0 * atan2(sqrt(x * x + y * y + z * z), abs(w))

    /**
     * Spherical linear interpolation from this (t = 0) to [o] (t = 1) along the shorter arc.
     * Both must be unit quaternions; the result is a unit quaternion.
     */
    public fun slerp(o: Quaternion, t: Double): Quaternion {
        val out = DoubleArray(4)
        Orientations.slerp(toDoubleArray(), o.toDoubleArray(), t, out)
        return Quaternion(out[0], out[1], out[2], out[3])
    }

    /** The rotation matrix of this unit quaternion: v_world = R · v ⇔ v_world = q ⊗ v ⊗ q*. */
    public fun toRotationMatrix(): RotationMatrix = RotationMatrix.fromQuaternion(this)

    /**
     * The rotation vector (axis · angle, radians, angle in [0, π]) of this unit quaternion: the
     * logarithm map, inverse of [fromRotationVector]. The zero vector for the identity.
     */
    public fun toRotationVector(): Vector3 {
        val c = canonical()
        val vn = sqrt(c.x * c.x + c.y * c.y + c.z * c.z)
        if (vn == 0.0) return Vector3.ZERO
        val angle = 2.0 * atan2(vn, c.w)
        return Vector3(c.x, c.y, c.z) * (angle / vn)
    }

    /** [w, x, y, z]. */
    public fun toDoubleArray(): DoubleArray = doubleArrayOf(w, x, y, z)

    public companion object {
        /** No rotation: the sensor frame coincides with the world frame. */
        public val IDENTITY: Quaternion = Quaternion(1.0, 0.0, 0.0, 0.0)

        /**
         * Rotation by [angleRad] radians about [axis] (right-hand rule; need not be unit length).
         * @throws IllegalArgumentException for a zero or non-finite axis.
         */
        public fun fromAxisAngle(axis: Vector3, angleRad: Double): Quaternion {
            val u = axis.normalized()
            val h = 0.5 * angleRad
            val s = sin(h)
            return Quaternion(cos(h), u.x * s, u.y * s, u.z * s)
        }

        /**
         * The rotation by the rotation vector [r] (axis · angle, radians): the exponential map.
         * Zero gives the identity.
         */
        public fun fromRotationVector(r: Vector3): Quaternion {
            val angle = r.norm()
            if (angle < 1e-12) return Quaternion(1.0, 0.5 * r.x, 0.5 * r.y, 0.5 * r.z).normalized()
            val s = sin(0.5 * angle) / angle
            return Quaternion(cos(0.5 * angle), r.x * s, r.y * s, r.z * s)
        }
    }
}
