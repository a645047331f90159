/*
 * RotationArrays: allocation-free conversions between quaternions and Android-style float
 * matrices, for per-sample code (the sensor callback, the filter's output to the display).
 *
 * Quaternions are DoubleArray [w, x, y, z] (orientation sensor → world, v_world = q ⊗ v ⊗ q*);
 * matrices are row-major FloatArray of 9 or 16 elements in Android's layout, mapping sensor →
 * world like getRotationMatrix's R. Nothing here allocates; all state is in locals (thread-safe).
 */
package dev.motionfusion.core

/** Allocation-free quaternion ⇄ float-matrix conversions (see the file header). */
public object RotationArrays {

    /**
     * Writes the rotation matrix of the quaternion [q] ([w, x, y, z], normalised on the fly) into
     * [r] (9 or 16 row-major elements, 16 with the homogeneous last row and column).
     * @throws IllegalArgumentException when [q] has not 4 elements or [r] not 9 or 16.
     */
    @JvmStatic
    public fun quaternionToRotationMatrix(q: DoubleArray, r: FloatArray) {
        require(q.size == 4) { "a quaternion has 4 elements [w, x, y, z], not ${q.size}" }
        require(r.size == 9 || r.size == 16) { "a row-major matrix has 9 or 16 elements, not ${r.size}" }
        val s = if (r.size == 9) 3 else 4
        quaternionToMatrix(q[0], q[1], q[2], q[3]) { m00, m01, m02, m10, m11, m12, m20, m21, m22 ->
            r[0] = m00.toFloat(); r[1] = m01.toFloat(); r[2] = m02.toFloat()
            r[s] = m10.toFloat(); r[s + 1] = m11.toFloat(); r[s + 2] = m12.toFloat()
            r[2 * s] = m20.toFloat(); r[2 * s + 1] = m21.toFloat(); r[2 * s + 2] = m22.toFloat()
        }
        if (s == 4) {
            r[3] = 0f; r[7] = 0f; r[11] = 0f; r[12] = 0f; r[13] = 0f; r[14] = 0f; r[15] = 1f
        }
    }

    /**
     * Writes the unit quaternion [w, x, y, z] (w ≥ 0) of the rotation matrix [r] (9 or 16
     * row-major elements) into [q], by Shepperd's method (robust near 180°).
     * @throws IllegalArgumentException when [r] has not 9 or 16 elements or [q] not 4.
     */
    @JvmStatic
    public fun rotationMatrixToQuaternion(r: FloatArray, q: DoubleArray) {
        require(r.size == 9 || r.size == 16) { "a row-major matrix has 9 or 16 elements, not ${r.size}" }
        require(q.size == 4) { "a quaternion has 4 elements [w, x, y, z], not ${q.size}" }
        val s = if (r.size == 9) 3 else 4
        shepperd(
            r[0].toDouble(), r[1].toDouble(), r[2].toDouble(),
            r[s].toDouble(), r[s + 1].toDouble(), r[s + 2].toDouble(),
            r[2 * s].toDouble(), r[2 * s + 1].toDouble(), r[2 * s + 2].toDouble(),
        ) { w, x, y, z ->
            q[0] = w; q[1] = x; q[2] = y; q[3] = z
        }
    }
}
