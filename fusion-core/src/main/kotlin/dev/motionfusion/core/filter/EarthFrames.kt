/*
 * Conversions used by the filter between its North-West-Up earth frame and the output frames,
 * and the initial orientation from one accelerometer and magnetometer reading.
 *
 * Quaternions [w, x, y, z], Hamilton, sensor → earth (v_earth = q ⊗ v ⊗ q*). Changing the earth
 * frame by a fixed rotation c (NWU coordinates → other coordinates) gives q_other = c ⊗ q_NWU:
 *   ENU: c = +90° about z = [cos 45°, 0, 0, sin 45°];   NED: c = 180° about x = [0, 1, 0, 0].
 */
package dev.motionfusion.core.filter

import kotlin.math.sqrt

internal object EarthFrames {
    private val H = sqrt(0.5)

    /** Writes c ⊗ [w, x, y, z] for [frame] into out[off..off+3]. */
    fun fromNwu(frame: OutputFrame, w: Double, x: Double, y: Double, z: Double, out: DoubleArray, off: Int) {
        when (frame) {
            OutputFrame.NWU -> { out[off] = w; out[off + 1] = x; out[off + 2] = y; out[off + 3] = z }
            OutputFrame.ENU -> { out[off] = H * (w - z); out[off + 1] = H * (x - y); out[off + 2] = H * (y + x); out[off + 3] = H * (z + w) }
            OutputFrame.NED -> { out[off] = -x; out[off + 1] = w; out[off + 2] = -z; out[off + 3] = y }
        }
    }

    /**
     * The NWU orientation of a sensor whose accelerometer reads ([ax], [ay], [az]) (up, any unit)
     * and, when [useMag], whose magnetometer reads ([mx], [my], [mz]), written to out[0..3].
     * Without a usable magnetometer (or with the field parallel to gravity) the heading is the one
     * of the smallest rotation taking the sensor's up to the earth's up. The accelerometer must be
     * finite and non-zero.
     */
    fun initial(ax: Double, ay: Double, az: Double, useMag: Boolean, mx: Double, my: Double, mz: Double, out: DoubleArray) {
        val an = 1.0 / sqrt(ax * ax + ay * ay + az * az)
        val ux = ax * an
        val uy = ay * an
        val uz = az * an
        if (useMag) {
            // west = up × m, north = west × up; the rows of R (sensor → NWU) are north, west, up.
            var wx = uy * mz - uz * my
            var wy = uz * mx - ux * mz
            var wz = ux * my - uy * mx
            val wn = sqrt(wx * wx + wy * wy + wz * wz)
            val mn = sqrt(mx * mx + my * my + mz * mz)
            if (wn > 1e-3 * mn) {
                wx /= wn; wy /= wn; wz /= wn
                val nx = wy * uz - wz * uy
                val ny = wz * ux - wx * uz
                val nz = wx * uy - wy * ux
                fromMatrix(nx, ny, nz, wx, wy, wz, ux, uy, uz, out)
                return
            }
        }
        // Shortest arc from u to z: [1 + u·z, u × z], normalised; 180° about x when u = −z.
        val w = 1.0 + uz
        if (w < 1e-12) {
            out[0] = 0.0; out[1] = 1.0; out[2] = 0.0; out[3] = 0.0
            return
        }
        val n = 1.0 / sqrt(w * w + uy * uy + ux * ux)
        out[0] = w * n; out[1] = uy * n; out[2] = -ux * n; out[3] = 0.0
    }

    /** Unit quaternion of the rotation matrix with rows (r00 r01 r02), (r10 r11 r12), (r20 r21 r22). */
    private fun fromMatrix(
        r00: Double, r01: Double, r02: Double,
        r10: Double, r11: Double, r12: Double,
        r20: Double, r21: Double, r22: Double,
        out: DoubleArray,
    ) {
        // Shepperd's method: divide by the largest of 4w², 4x², 4y², 4z² for accuracy.
        val t = r00 + r11 + r22
        val w: Double
        val x: Double
        val y: Double
        val z: Double
        if (t > r00 && t > r11 && t > r22) {
            val s = 2.0 * sqrt(1.0 + t)
            w = 0.25 * s; x = (r21 - r12) / s; y = (r02 - r20) / s; z = (r10 - r01) / s
        } else if (r00 > r11 && r00 > r22) {
            val s = 2.0 * sqrt(1.0 + r00 - r11 - r22)
            w = (r21 - r12) / s; x = 0.25 * s; y = (r01 + r10) / s; z = (r02 + r20) / s
        } else if (r11 > r22) {
            val s = 2.0 * sqrt(1.0 + r11 - r00 - r22)
            w = (r02 - r20) / s; x = (r01 + r10) / s; y = 0.25 * s; z = (r12 + r21) / s
        } else {
            val s = 2.0 * sqrt(1.0 + r22 - r00 - r11)
            w = (r10 - r01) / s; x = (r02 + r20) / s; y = (r12 + r21) / s; z = 0.25 * s
        }
        val n = 1.0 / sqrt(w * w + x * x + y * y + z * z)
        out[0] = w * n; out[1] = x * n; out[2] = y * n; out[3] = z * n
    }
}
