/*
 * RotationMatrix: an immutable 3×3 matrix, row-major like Android's (mRC = row R, column C).
 *
 * Used as an orientation it maps sensor (device) coordinates to world coordinates,
 * v_world = M · v_sensor, the direction of Android's getRotationMatrix R and of the quaternion
 * q with M = R(q) (v_world = q ⊗ v ⊗ q*). Its rows are the world axes in sensor coordinates;
 * its columns are the sensor axes in world coordinates. Which world (ENU, NWU, NED) is stated by
 * whoever produces it; see docs/CONVENTIONS.md.
 */
package dev.motionfusion.core

import kotlin.math.cos
import kotlin.math.sin
import kotlin.math.sqrt

/** An immutable row-major 3×3 matrix, normally a rotation (sensor → world). */
public data class RotationMatrix(
    val m00: Double, val m01: Double, val m02: Double,
    val m10: Double, val m11: Double, val m12: Double,
    val m20: Double, val m21: Double, val m22: Double,
) {

    /** Element at [row], [column] (0..2 each). */
    public operator fun get(row: Int, column: Int): Double {
        require(row in 0..2 && column in 0..2) { "index ($row, $column) not in 0..2" }
        return when (row * 3 + column) {
            0 -> m00; 1 -> m01; 2 -> m02
            3 -> m10; 4 -> m11; 5 -> m12
            6 -> m20; 7 -> m21; else -> m22
        }
    }

    /** Matrix product this · o (apply [o] first, then this). */
    public operator fun times(o: RotationMatrix): RotationMatrix = RotationMatrix(
        m00 * o.m00 + m01 * o.m10 + m02 * o.m20, m00 * o.m01 + m01 * o.m11 + m02 * o.m21, m00 * o.m02 + m01 * o.m12 + m02 * o.m22,
        m10 * o.m00 + m11 * o.m10 + m12 * o.m20, m10 * o.m01 + m11 * o.m11 + m12 * o.m21, m10 * o.m02 + m11 * o.m12 + m12 * o.m22,
        m20 * o.m00 + m21 * o.m10 + m22 * o.m20, m20 * o.m01 + m21 * o.m11 + m22 * o.m21, m20 * o.m02 + m21 * o.m12 + m22 * o.m22,
    )

    /** This · [v]: for an orientation, takes a sensor-frame vector into the world frame. */
    public operator fun times(v: Vector3): Vector3 = Vector3(
        m00 * v.x + m01 * v.y + m02 * v.z,
        m10 * v.x + m11 * v.y + m12 * v.z,
        m20 * v.x + m21 * v.y + m22 * v.z,
    )

    /** The transpose, which is the inverse of a rotation (world → sensor for an orientation). */
    public fun transpose(): RotationMatrix = RotationMatrix(m00, m10, m20, m01, m11, m21, m02, m12, m22)

    /** The determinant: +1 for a rotation, −1 for a reflection. */
    public fun determinant(): Double =
        m00 * (m11 * m22 - m12 * m21) - m01 * (m10 * m22 - m12 * m20) + m02 * (m10 * m21 - m11 * m20)

    /**
     * True when this is a proper rotation within [tolerance]: ‖I − MᵀM‖_F < tolerance (the test
     * of seed 004's isRotationMatrix, whose tolerance 1e-6 is the default) and det M > 0 (which
     * seed 004 omits, so it would accept reflections).
     */
    public fun isRotationMatrix(tolerance: Double = 1e-6): Boolean {
        val p = transpose() * this
        val d = doubleArrayOf(
            1.0 - p.m00, p.m01, p.m02,
            p.m10, 1.0 - p.m11, p.m12,
            p.m20, p.m21, 1.0 - p.m22,
        )
        return sqrt(d.sumOf { it * it }) < tolerance && determinant() > 0.0
    }

    /**
     * The unit quaternion (w ≥ 0) of this rotation, by Shepperd's method: the largest of
     * 4w², 4x², 4y², 4z² (from the trace and the diagonal) is taken as the pivot, so no division
     * by a small number happens for any rotation, including those near 180°.
     * Assumes a rotation matrix; for a slightly non-orthogonal one the result is renormalised.
     */
    public fun toQuaternion(): Quaternion =
        shepperd(m00, m01, m02, m10, m11, m12, m20, m21, m22) { w, x, y, z -> Quaternion(w, x, y, z) }

    /** Row-major elements, 9 (3×3) or 16 (4×4 homogeneous, as Android's 16-element layout). */
    public fun toFloatArray(size: Int = 9): FloatArray {
        require(size == 9 || size == 16) { "a row-major matrix has 9 or 16 elements, not $size" }
        val out = FloatArray(size)
        val s = if (size == 9) 3 else 4
        for (r in 0..2) for (c in 0..2) out[r * s + c] = get(r, c).toFloat()
        if (size == 16) out[15] = 1f
        return out
    }

    /** The 9 row-major elements. */
    public fun toDoubleArray(): DoubleArray = doubleArrayOf(m00, m01, m02, m10, m11, m12, m20, m21, m22)

    public companion object {
        /** The identity: the sensor frame coincides with the world frame. */
        public val IDENTITY: RotationMatrix = RotationMatrix(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0)

        /**
         * From row-major [values]: 9 elements (3×3) or 16 (4×4, as Android's; the upper-left 3×3
         * is taken). Does not check that it is a rotation (see [isRotationMatrix]).
         * @throws IllegalArgumentException for another length.
         */
        public fun fromRowMajor(values: FloatArray): RotationMatrix {
            require(values.size == 9 || values.size == 16) {
                "a row-major matrix has 9 or 16 elements, not ${values.size}"
            }
            val s = if (values.size == 9) 3 else 4
            fun e(r: Int, c: Int) = values[r * s + c].toDouble()
            return RotationMatrix(e(0, 0), e(0, 1), e(0, 2), e(1, 0), e(1, 1), e(1, 2), e(2, 0), e(2, 1), e(2, 2))
        }

        /** The matrix of the unit quaternion [q]: v_world = R(q) · v ⇔ v_world = q ⊗ v ⊗ q*. */
        public fun fromQuaternion(q: Quaternion): RotationMatrix =
            quaternionToMatrix(q.w, q.x, q.y, q.z, ::RotationMatrix)

        /**
         * Rotation by [angleRad] radians about the coordinate axis [axis] (0 = x, 1 = y, 2 = z),
         * right-hand rule: Rx, Ry, Rz of seed 004.
         */
        public fun aboutAxis(axis: Int, angleRad: Double): RotationMatrix {
            val c = cos(angleRad)
            val s = sin(angleRad)
            return when (axis) {
                0 -> RotationMatrix(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
                1 -> RotationMatrix(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
                2 -> RotationMatrix(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
                else -> throw IllegalArgumentException("axis $axis not in 0..2")
            }
        }
    }
}

/**
 * The rotation matrix elements of the quaternion [w, x, y, z] (made unit length first), handed to
 * [build] row-major. Shared by the immutable and the allocation-free array paths.
 */
internal inline fun <T> quaternionToMatrix(
    w: Double, x: Double, y: Double, z: Double,
    build: (Double, Double, Double, Double, Double, Double, Double, Double, Double) -> T,
): T {
    val n2 = w * w + x * x + y * y + z * z
    val s = 2.0 / n2 // scaling by 2/|q|² makes a non-unit q give a rotation too
    val xx = s * x * x; val yy = s * y * y; val zz = s * z * z
    val xy = s * x * y; val xz = s * x * z; val yz = s * y * z
    val wx = s * w * x; val wy = s * w * y; val wz = s * w * z
    return build(
        1.0 - yy - zz, xy - wz, xz + wy,
        xy + wz, 1.0 - xx - zz, yz - wx,
        xz - wy, yz + wx, 1.0 - xx - yy,
    )
}

/**
 * The rotation matrix of the unit quaternion [w, x, y, z] (|q| = 1 taken as given, not normalised),
 * handed to [build] row-major: R = [1 − 2(y² + z²), 2(xy − wz), 2(xz + wy); 2(xy + wz), 1 − 2(x² + z²),
 * 2(yz − wx); 2(xz − wy), 2(yz + wx), 1 − 2(x² + y²)]. The per-sample code's one copy of these terms
 * (angles, linear acceleration, the heading of a field); a caller that needs a few elements takes
 * them and the compiler drops the rest. [quaternionToMatrix] is the normalising form.
 */
internal inline fun <T> unitQuaternionToMatrix(
    w: Double, x: Double, y: Double, z: Double,
    build: (Double, Double, Double, Double, Double, Double, Double, Double, Double) -> T,
): T = unitQuaternionUp(w, x, y, z) { r20, r21, r22 ->
    build(
        1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y),
        2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x),
        r20, r21, r22,
    )
}

/**
 * Up (the world's z axis) in the sensor frame for the unit quaternion [w, x, y, z] (sensor → world),
 * handed to [build]: the third row of [unitQuaternionToMatrix], q* ⊗ [0, 0, 0, 1] ⊗ q.
 */
internal inline fun <T> unitQuaternionUp(w: Double, x: Double, y: Double, z: Double, build: (Double, Double, Double) -> T): T =
    build(2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y))

/** [unitQuaternionToMatrix] of the quaternion at [q][[at]..[at] + 3]. */
internal inline fun <T> unitQuaternionToMatrix(
    q: DoubleArray, at: Int,
    build: (Double, Double, Double, Double, Double, Double, Double, Double, Double) -> T,
): T = unitQuaternionToMatrix(q[at], q[at + 1], q[at + 2], q[at + 3], build)

/** [unitQuaternionUp] of the quaternion at [q][[at]..[at] + 3]. */
internal inline fun <T> unitQuaternionUp(q: DoubleArray, at: Int, build: (Double, Double, Double) -> T): T =
    unitQuaternionUp(q[at], q[at + 1], q[at + 2], q[at + 3], build)

/**
 * Shepperd's method: the unit quaternion (w ≥ 0) of a rotation matrix, handed to [build].
 * 4w² = 1 + tr, 4x² = 1 + m00 − m11 − m22, 4y² = 1 − m00 + m11 − m22, 4z² = 1 − m00 − m11 + m22;
 * the largest is the pivot p, its component is √(4p²)/2 and the others come from the
 * off-diagonal sums and differences divided by 4·pivot, which is never small (≥ 1/2 for a rotation).
 */
internal inline fun <T> shepperd(
    m00: Double, m01: Double, m02: Double,
    m10: Double, m11: Double, m12: Double,
    m20: Double, m21: Double, m22: Double,
    build: (Double, Double, Double, Double) -> T,
): T {
    val tw = 1.0 + m00 + m11 + m22
    val tx = 1.0 + m00 - m11 - m22
    val ty = 1.0 - m00 + m11 - m22
    val tz = 1.0 - m00 - m11 + m22
    val w: Double; val x: Double; val y: Double; val z: Double
    if (tw >= tx && tw >= ty && tw >= tz) {
        w = tw; x = m21 - m12; y = m02 - m20; z = m10 - m01
    } else if (tx >= ty && tx >= tz) {
        w = m21 - m12; x = tx; y = m01 + m10; z = m02 + m20
    } else if (ty >= tz) {
        w = m02 - m20; x = m01 + m10; y = ty; z = m12 + m21
    } else {
        w = m10 - m01; x = m02 + m20; y = m12 + m21; z = tz
    }
    // (w, x, y, z) is now 4·pivot·q; normalising removes the factor (and any non-orthogonality).
    val n = sqrt(w * w + x * x + y * y + z * z)
    val k = (if (w < 0.0) -1.0 else 1.0) / n
    return build(w * k, x * k, y * k, z * k)
}
