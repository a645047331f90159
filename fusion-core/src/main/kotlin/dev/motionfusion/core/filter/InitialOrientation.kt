/*
 * The filter's starting orientation from one accelerometer and magnetometer reading, as
 * getRotationMatrix finds it, in the report's North-West-Up earth frame.
 *
 * Quaternions [w, x, y, z], Hamilton, sensor → earth (v_earth = q ⊗ v ⊗ q*). Inputs in the Android
 * device frame; any units (only directions matter).
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.RotationMatrix
import kotlin.math.sqrt

internal object InitialOrientation {
    /**
     * The NWU orientation of a sensor whose accelerometer reads ([ax], [ay], [az]) (up) and, when
     * [useMag], whose magnetometer reads ([mx], [my], [mz]). Without a usable magnetometer (or with
     * the field parallel to gravity) the heading is that of the smallest rotation taking the
     * sensor's up to the earth's up. The accelerometer must be finite and non-zero.
     */
    fun nwu(ax: Double, ay: Double, az: Double, useMag: Boolean, mx: Double, my: Double, mz: Double): Quaternion {
        val an = 1.0 / sqrt(ax * ax + ay * ay + az * az)
        val ux = ax * an
        val uy = ay * an
        val uz = az * an
        if (useMag) {
            // west = up × m, north = west × up; the rows of R (sensor → NWU) are north, west, up.
            val wx = uy * mz - uz * my
            val wy = uz * mx - ux * mz
            val wz = ux * my - uy * mx
            val wn = sqrt(wx * wx + wy * wy + wz * wz)
            if (wn > 1e-3 * sqrt(mx * mx + my * my + mz * mz)) {
                val w = 1.0 / wn
                return RotationMatrix(
                    (wy * uz - wz * uy) * w, (wz * ux - wx * uz) * w, (wx * uy - wy * ux) * w,
                    wx * w, wy * w, wz * w,
                    ux, uy, uz,
                ).toQuaternion()
            }
        }
        // Shortest arc from u to z: [1 + u·z, u × z] normalised (u × z keeps the axis even where
        // 1 + u·z cancels); 180° about x when u = −z exactly.
        val w = 1.0 + uz
        if (ux == 0.0 && uy == 0.0 && w <= 0.0) return Quaternion(0.0, 1.0, 0.0, 0.0)
        return Quaternion(w, uy, -ux, 0.0).normalized()
    }
}
