/*
 * The one home of the orientation conversions that everything else shows or scores with: the
 * replay CSV, `fusion compare` and `fusion plot`, BROAD's metric in eval, and the app's display.
 *
 * Orientations are unit quaternions [w, x, y, z], Hamilton, sensor → ENU (docs/CONVENTIONS.md),
 * either as Quaternion or, on hot paths, as DoubleArray read from index 0 (no allocation).
 * Angles in radians.
 *
 *  - Android angles: SensorManager.getOrientation of R(q): azimuth atan2(R01, R11), pitch
 *    asin(−R21) (clamped, so a slightly non-unit q gives no NaN), roll atan2(−R20, R22).
 *  - Aerospace angles of the phone as an aircraft: intrinsic Z-Y-X yaw/pitch/roll of the body
 *    frame x forward = device y, y right = device x, z down = −device z, in North-East-Down. Yaw is
 *    the azimuth, pitch is minus Android's pitch, roll is Android's roll, except at gimbal lock
 *    (top edge vertical), where Z-Y-X puts the whole rotation in yaw and roll is 0.
 *  - Slerp along the shorter arc.
 *  - The error of an estimate q against a reference r as BROAD splits it (Laidig et al. 2021):
 *    e = q ⊗ r* (an earth-frame rotation); total 2·atan2(|e_xyz|, |e_w|), heading (about the
 *    vertical) 2·atan|e_z / e_w|, inclination 2·acos √(e_w² + e_z²). The inclination is the angle
 *    between the two orientations' up directions in the sensor frame: the tilt difference alone.
 */
package dev.motionfusion.core

import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.asin
import kotlin.math.atan
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.min
import kotlin.math.sin
import kotlin.math.sqrt

/**
 * Android's orientation angles (as getOrientation), radians, of a device → ENU rotation R:
 * [azimuth] about −z, from magnetic north to the device's y axis projected on the ground,
 * positive toward east, in [−π, π]; [pitch] about x, positive when the top edge tilts down,
 * in [−π/2, π/2]; [roll] about y, positive when the right edge tilts down, in [−π, π].
 * R = Rz(−azimuth) · Rx(−pitch) · Ry(roll), i.e. intrinsic Z-X-Y angles (−azimuth, −pitch, roll).
 * When pitch is ±π/2 azimuth and roll are not separable; like getOrientation, both are still
 * computed from atan2 and are then only as meaningful as the matrix's rounding.
 */
public data class AndroidAngles(val azimuth: Double, val pitch: Double, val roll: Double) {
    public val azimuthDeg: Double get() = Math.toDegrees(azimuth)
    public val pitchDeg: Double get() = Math.toDegrees(pitch)
    public val rollDeg: Double get() = Math.toDegrees(roll)

    /** The device → ENU rotation matrix Rz(−azimuth)·Rx(−pitch)·Ry(roll). */
    public fun toRotationMatrix(): RotationMatrix =
        EulerAngles(-azimuth, -pitch, roll, EulerSequence.ZXY, EulerMode.INTRINSIC).toRotationMatrix()
}

/** BROAD's split of an orientation error, radians: [total] in [0, π], [heading] and [inclination] in [0, π]. */
public data class ErrorAngles(val total: Double, val heading: Double, val inclination: Double)

public object Orientations {
    /** Android's angles of the device → ENU matrix [r]. */
    @JvmStatic
    public fun androidAngles(r: RotationMatrix): AndroidAngles =
        AndroidAngles(atan2(r.m01, r.m11), asin((-r.m21).coerceIn(-1.0, 1.0)), atan2(-r.m20, r.m22))

    /** Android's angles of the unit quaternion [q] (sensor → ENU). */
    @JvmStatic
    public fun androidAngles(q: Quaternion): AndroidAngles {
        val out = DoubleArray(6)
        androidAndAerospaceAngles(q.toDoubleArray(), 0, out, 0)
        return AndroidAngles(out[0], out[1], out[2])
    }

    /** The azimuth of [q] ([w, x, y, z], sensor → ENU): the heading of the device's y axis, east of north. */
    @JvmStatic
    public fun azimuth(q: DoubleArray): Double =
        unitQuaternionToMatrix(q, 0) { _, r01, _, _, r11, _, _, _, _ -> atan2(r01, r11) }

    /** The aerospace yaw, pitch, roll of the phone as an aircraft (see the file header) for [q] (sensor → ENU). */
    @JvmStatic
    public fun phoneAerospaceAngles(q: Quaternion): AerospaceAngles {
        val out = DoubleArray(6)
        androidAndAerospaceAngles(q.toDoubleArray(), out, 0)
        return AerospaceAngles(out[3], out[4], out[5])
    }

    /**
     * Android's azimuth, pitch, roll into out[offset..offset+2] and the phone-as-aircraft yaw,
     * pitch, roll into out[offset+3..offset+5], radians, of [q] ([w, x, y, z], sensor → ENU), from
     * one rotation matrix. NaN in, NaN out.
     */
    @JvmStatic
    public fun androidAndAerospaceAngles(q: DoubleArray, out: DoubleArray, offset: Int): Unit = androidAndAerospaceAngles(q, 0, out, offset)

    /** As [androidAndAerospaceAngles] with q at q[qAt..qAt+3]. */
    @JvmStatic
    public fun androidAndAerospaceAngles(q: DoubleArray, qAt: Int, out: DoubleArray, offset: Int): Unit =
        unitQuaternionToMatrix(q, qAt) { r00, r01, _, r10, r11, _, r20, r21, r22 -> anglesOf(r00, r01, r10, r11, r20, r21, r22, out, offset) }

    /** [androidAndAerospaceAngles] from the elements of the rotation matrix it needs. */
    @Suppress("NOTHING_TO_INLINE")
    private inline fun anglesOf(r00: Double, r01: Double, r10: Double, r11: Double, r20: Double, r21: Double, r22: Double, out: DoubleArray, offset: Int) {
        // Fdlibm's asin and atan2 are exactly Math's, faster on the JVM (Fdlibm.kt).
        val azimuth = Fdlibm.atan2(r01, r11)
        val pitch = Fdlibm.asin((-r21).coerceIn(-1.0, 1.0))
        val roll = Fdlibm.atan2(-r20, r22)
        out[offset] = azimuth
        out[offset + 1] = pitch
        out[offset + 2] = roll
        // Aerospace body→NED matrix M = C·R·P has M00 = R11, M10 = R01, M20 = −R21, M21 = −R20,
        // M22 = R22, M01 = R10, M11 = R00 (C: ENU→NED, P: body→device). So yaw = atan2(M10, M00)
        // is the azimuth, pitch = asin(−M20) = −(Android pitch), roll = atan2(M21, M22) is the
        // Android roll, except at gimbal lock, where Z-Y-X puts the whole rotation in yaw.
        out[offset + 4] = -pitch
        if (!(r11 * r11 + r01 * r01 < GIMBAL_LOCK_THRESHOLD * GIMBAL_LOCK_THRESHOLD)) { // NaN stays NaN
            out[offset + 3] = azimuth
            out[offset + 5] = roll
        } else {
            out[offset + 3] = Fdlibm.atan2(-r10, r00)
            out[offset + 5] = 0.0
        }
    }

    /** Spherical interpolation of unit quaternions [a] (t = 0) to [b] (t = 1) along the shorter arc, into [out] (unit). */
    @JvmStatic
    public fun slerp(a: DoubleArray, b: DoubleArray, t: Double, out: DoubleArray) {
        var d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
        val sign = if (d < 0) -1.0 else 1.0
        d *= sign
        val s0: Double
        val s1: Double
        if (d > 0.9995) {
            // Nearly parallel: linear interpolation then normalisation is accurate and safe.
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

    /** e = [q] ⊗ [r]* into [e] ([w, x, y, z]): the earth-frame rotation from the reference to the estimate. */
    @JvmStatic
    public fun errorQuaternion(q: DoubleArray, r: DoubleArray, e: DoubleArray) {
        val w = q[0] * r[0] + q[1] * r[1] + q[2] * r[2] + q[3] * r[3]
        val x = -q[0] * r[1] + q[1] * r[0] - q[2] * r[3] + q[3] * r[2]
        val y = -q[0] * r[2] + q[1] * r[3] + q[2] * r[0] - q[3] * r[1]
        val z = -q[0] * r[3] - q[1] * r[2] + q[2] * r[1] + q[3] * r[0]
        e[0] = w; e[1] = x; e[2] = y; e[3] = z
    }

    /** The signed heading of the error quaternion [e] (its rotation about the vertical), rad in [−π, π]. */
    @JvmStatic
    public fun signedHeading(e: DoubleArray): Double = if (e[0] < 0.0) 2.0 * atan2(-e[3], -e[0]) else 2.0 * atan2(e[3], e[0])

    /**
     * [e] turned by −[headingRad] about the vertical (Rz(−ψ) ⊗ e), in place: removes a constant
     * heading offset (6D filters, the game rotation vector) before [splitError].
     */
    @JvmStatic
    public fun removeHeading(e: DoubleArray, headingRad: Double) {
        val c = cos(0.5 * headingRad)
        val s = -sin(0.5 * headingRad)
        val w = c * e[0] - s * e[3]
        val x = c * e[1] - s * e[2]
        val y = c * e[2] + s * e[1]
        val z = c * e[3] + s * e[0]
        e[0] = w; e[1] = x; e[2] = y; e[3] = z
    }

    /** Total, heading and inclination (rad) of the error quaternion [e] (any norm) into out[offset..offset+2]. */
    @JvmStatic
    public fun splitError(e: DoubleArray, out: DoubleArray, offset: Int) {
        val n = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3])
        val aw = abs(e[0]) / n
        val az = e[3] / n
        out[offset] = 2.0 * atan2(sqrt(e[1] * e[1] + e[2] * e[2] + e[3] * e[3]) / n, aw)
        out[offset + 1] = 2.0 * atan(abs(az / aw))
        out[offset + 2] = 2.0 * acos(min(1.0, sqrt(aw * aw + az * az)))
    }

    /** BROAD's split of the error of [estimate] against [reference] (unit quaternions, same earth frame). */
    @JvmStatic
    public fun error(estimate: Quaternion, reference: Quaternion): ErrorAngles {
        val e = DoubleArray(4)
        errorQuaternion(estimate.toDoubleArray(), reference.toDoubleArray(), e)
        val out = DoubleArray(3)
        splitError(e, out, 0)
        return ErrorAngles(out[0], out[1], out[2])
    }
}
