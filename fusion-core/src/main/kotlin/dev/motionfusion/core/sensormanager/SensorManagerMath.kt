/*
 * SensorManagerMath: faithful ports of the static math of android.hardware.SensorManager
 * (AOSP core/java/android/hardware/SensorManager.java, as shipped in android-all 14), with the
 * same names, float-array signatures, constants, boolean returns and float/double casts, so that
 * every result is bit-identical to the platform's (proven by SensorManagerMathDifferentialTest).
 *
 * Frames: the device (sensor) frame is Android's (x right, y up along the screen, z out of the
 * screen); the world frame is ENU (x ≈ east = y × z, y magnetic north, z up, away from gravity).
 * A rotation matrix R maps device coordinates to world coordinates: v_world = R · v_device.
 * Matrices are row-major, 9 elements (3×3) or 16 elements (4×4, homogeneous, last row/column
 * 0 0 0 1). Units: m/s² (any unit works for directions), µT, rad, hPa, m.
 *
 * Differences from AOSP, all invisible in the outputs:
 *  - AOSP's remapCoordinateSystem routes in == out through a shared static temp matrix under a
 *    lock; this port keeps the row in locals instead, so it allocates nothing and is thread-safe.
 *    The observable results are the same, including AOSP's quirk that in == out with 9 elements
 *    remaps in place (the static temp has 16 elements, so the temp route fails and AOSP falls
 *    back to writing the input while reading it): such a call returns true but the result is the
 *    partially overwritten matrix. Use the typed [remapCoordinateSystem] wrapper to avoid it.
 *  - Nothing here allocates; nothing is shared between threads.
 * Like AOSP, these functions do not validate lengths beyond what AOSP checks: arrays shorter than
 * what is read throw ArrayIndexOutOfBoundsException, and matrices of other lengths are ignored
 * where AOSP ignores them. The typed wrappers in AndroidSensorMath.kt validate their input.
 */
package dev.motionfusion.core.sensormanager

import kotlin.math.asin
import kotlin.math.atan2
import kotlin.math.pow
import kotlin.math.sqrt

/** Ports of `android.hardware.SensorManager`'s static math and constants (see the file header). */
public object SensorManagerMath {

    /** Standard gravity, m/s² (AOSP `STANDARD_GRAVITY`). */
    public const val STANDARD_GRAVITY: Float = 9.80665f

    /** Earth's gravity, m/s² (AOSP `GRAVITY_EARTH`, equal to [STANDARD_GRAVITY]). */
    public const val GRAVITY_EARTH: Float = 9.80665f

    /** Maximum magnetic field on Earth's surface, µT (AOSP `MAGNETIC_FIELD_EARTH_MAX`). */
    public const val MAGNETIC_FIELD_EARTH_MAX: Float = 60.0f

    /** Minimum magnetic field on Earth's surface, µT (AOSP `MAGNETIC_FIELD_EARTH_MIN`). */
    public const val MAGNETIC_FIELD_EARTH_MIN: Float = 30.0f

    /** Standard atmosphere, pressure at sea level, hPa (AOSP `PRESSURE_STANDARD_ATMOSPHERE`). */
    public const val PRESSURE_STANDARD_ATMOSPHERE: Float = 1013.25f

    /** Axis constants of [remapCoordinateSystem] (AOSP values). */
    public const val AXIS_X: Int = 1
    public const val AXIS_Y: Int = 2
    public const val AXIS_Z: Int = 3
    public const val AXIS_MINUS_X: Int = AXIS_X or 0x80
    public const val AXIS_MINUS_Y: Int = AXIS_Y or 0x80
    public const val AXIS_MINUS_Z: Int = AXIS_Z or 0x80

    /**
     * The gravity AOSP's free-fall test uses: the literal 9.81f of getRotationMatrix, not
     * [GRAVITY_EARTH].
     */
    internal const val FREE_FALL_NOMINAL_GRAVITY: Float = 9.81f

    /** getRotationMatrix fails when |gravity|² is below this (10 % of 9.81 m/s², squared). */
    internal const val FREE_FALL_GRAVITY_SQUARED: Float =
        0.01f * FREE_FALL_NOMINAL_GRAVITY * FREE_FALL_NOMINAL_GRAVITY

    /** getRotationMatrix fails when |E × A| is below this (free fall, or near a magnetic pole). */
    internal const val MIN_HORIZONTAL_FIELD: Float = 0.1f

    /** The exponent 1/5.255 of the barometric formula in [getAltitude], as AOSP rounds it. */
    private const val ALTITUDE_EXPONENT: Float = 1.0f / 5.255f

    /** The 44330 m scale of the barometric formula in [getAltitude]. */
    private const val ALTITUDE_SCALE_M: Float = 44330.0f

    /**
     * Rotation matrix R (device → world ENU) and inclination matrix I (a rotation about the world
     * x axis taking the geomagnetic vector into the world frame) from a gravity vector (the
     * accelerometer at rest: pointing up, device frame, m/s²) and a geomagnetic vector (device
     * frame, µT). [R] and [I] may be null; each is written as 9 or 16 row-major elements
     * according to its length (other lengths are left alone).
     *
     * @return false, leaving [R] and [I] untouched, when |gravity|² < 0.01·9.81² (free fall) or
     *   |geomagnetic × gravity| < 0.1 (free fall, or near a magnetic pole).
     */
    @JvmStatic
    public fun getRotationMatrix(R: FloatArray?, I: FloatArray?, gravity: FloatArray, geomagnetic: FloatArray): Boolean {
        var ax = gravity[0]
        var ay = gravity[1]
        var az = gravity[2]
        val normSqA = ax * ax + ay * ay + az * az
        if (normSqA < FREE_FALL_GRAVITY_SQUARED) return false
        val ex = geomagnetic[0]
        val ey = geomagnetic[1]
        val ez = geomagnetic[2]
        // H = E × A points east.
        var hx = ey * az - ez * ay
        var hy = ez * ax - ex * az
        var hz = ex * ay - ey * ax
        val normH = sqrt((hx * hx + hy * hy + hz * hz).toDouble()).toFloat()
        if (normH < MIN_HORIZONTAL_FIELD) return false
        val invH = 1.0f / normH
        hx *= invH
        hy *= invH
        hz *= invH
        val invA = 1.0f / sqrt((ax * ax + ay * ay + az * az).toDouble()).toFloat()
        ax *= invA
        ay *= invA
        az *= invA
        // M = A × H points to magnetic north.
        val mx = ay * hz - az * hy
        val my = az * hx - ax * hz
        val mz = ax * hy - ay * hx
        if (R != null) {
            if (R.size == 9) {
                R[0] = hx; R[1] = hy; R[2] = hz
                R[3] = mx; R[4] = my; R[5] = mz
                R[6] = ax; R[7] = ay; R[8] = az
            } else if (R.size == 16) {
                R[0] = hx; R[1] = hy; R[2] = hz; R[3] = 0f
                R[4] = mx; R[5] = my; R[6] = mz; R[7] = 0f
                R[8] = ax; R[9] = ay; R[10] = az; R[11] = 0f
                R[12] = 0f; R[13] = 0f; R[14] = 0f; R[15] = 1f
            }
        }
        if (I != null) {
            // Project the geomagnetic vector on north (c) and up (s).
            val invE = 1.0f / sqrt((ex * ex + ey * ey + ez * ez).toDouble()).toFloat()
            val c = (ex * mx + ey * my + ez * mz) * invE
            val s = (ex * ax + ey * ay + ez * az) * invE
            if (I.size == 9) {
                I[0] = 1f; I[1] = 0f; I[2] = 0f
                I[3] = 0f; I[4] = c; I[5] = s
                I[6] = 0f; I[7] = -s; I[8] = c
            } else if (I.size == 16) {
                I[0] = 1f; I[1] = 0f; I[2] = 0f
                I[4] = 0f; I[5] = c; I[6] = s
                I[8] = 0f; I[9] = -s; I[10] = c
                I[3] = 0f; I[7] = 0f; I[11] = 0f; I[12] = 0f; I[13] = 0f; I[14] = 0f
                I[15] = 1f
            }
        }
        return true
    }

    /**
     * Geomagnetic inclination (dip) angle in radians from the inclination matrix [I] of
     * [getRotationMatrix] (9 elements, else read as 16): positive when the field points down.
     */
    @JvmStatic
    public fun getInclination(I: FloatArray): Float =
        if (I.size == 9) atan2(I[5].toDouble(), I[4].toDouble()).toFloat()
        else atan2(I[6].toDouble(), I[5].toDouble()).toFloat()

    /**
     * Rewrites the rotation matrix [inR] (device → world) for a new device frame in which the
     * original x axis lies along the new axis [X] and the original y axis along the new axis [Y]
     * (AXIS_* constants; e.g. display rotation 90°: X = AXIS_Y, Y = AXIS_MINUS_X), into [outR]:
     * out = in · Sᵀ with S = [X | Y | X × Y] as signed unit vectors. [inR] and
     * [outR] must have the same length (9 or 16; like AOSP, any other length is treated as 3 rows
     * of 3, and throws ArrayIndexOutOfBoundsException below 9).
     * 16-element outputs get the homogeneous last row and column.
     *
     * @return false, leaving [outR] untouched, for a length mismatch, an invalid axis or two
     *   axes along the same line. In == out with 16 elements works; with 9 elements it remaps
     *   in place exactly as AOSP does (see the file header).
     */
    @JvmStatic
    public fun remapCoordinateSystem(inR: FloatArray, X: Int, Y: Int, outR: FloatArray): Boolean {
        // AOSP: in == out goes through a 16-element temp (equivalent to reading each row before
        // writing it); when that fails (9 elements) AOSP remaps in place, reading what it wrote.
        val inPlace = inR === outR && outR.size != 16
        val length = outR.size
        if (inR.size != length) return false
        if ((X and 0x7C) != 0 || (Y and 0x7C) != 0) return false // bits 2..6 must be 0
        if ((X and 0x3) == 0 || (Y and 0x3) == 0) return false // no axis given
        if ((X and 0x3) == (Y and 0x3)) return false // same axis
        // The new z axis is X × Y: its axis is the remaining one, its sign from the parity.
        var zAxis = X xor Y
        val x = (X and 0x3) - 1
        val y = (Y and 0x3) - 1
        val z = (zAxis and 0x3) - 1
        val axisY = (z + 1) % 3
        val axisZ = (z + 2) % 3
        if ((x xor axisY) or (y xor axisZ) != 0) zAxis = zAxis xor 0x80
        val sx = X >= 0x80
        val sy = Y >= 0x80
        val sz = zAxis >= 0x80
        val rowLength = if (length == 16) 4 else 3
        for (j in 0 until 3) {
            val offset = j * rowLength
            val r0 = inR[offset]
            val r1 = inR[offset + 1]
            val r2 = inR[offset + 2]
            for (i in 0 until 3) {
                val sourceColumn = if (x == i) 0 else if (y == i) 1 else 2
                val v = if (inPlace) inR[offset + sourceColumn] else when (sourceColumn) {
                    0 -> r0
                    1 -> r1
                    else -> r2
                }
                val negate = if (x == i) sx else if (y == i) sy else sz
                outR[offset + i] = if (negate) -v else v
            }
        }
        if (length == 16) {
            outR[3] = 0f; outR[7] = 0f; outR[11] = 0f
            outR[12] = 0f; outR[13] = 0f; outR[14] = 0f
            outR[15] = 1f
        }
        return true
    }

    /**
     * Android's orientation angles, radians, from a rotation matrix [R] (device → world ENU;
     * 9 elements, else read as 16) into [values] (3 elements), which is returned:
     * values[0] azimuth = atan2(R01, R11), angle from magnetic north to the device's y axis
     * projected on the ground, positive toward east, in [−π, π];
     * values[1] pitch = asin(−R21), in [−π/2, π/2] (NaN if |R21| > 1: use the typed wrapper);
     * values[2] roll = atan2(−R20, R22), in [−π, π].
     */
    @JvmStatic
    public fun getOrientation(R: FloatArray, values: FloatArray): FloatArray {
        if (R.size == 9) {
            values[0] = atan2(R[1].toDouble(), R[4].toDouble()).toFloat()
            values[1] = asin((-R[7]).toDouble()).toFloat()
            values[2] = atan2((-R[6]).toDouble(), R[8].toDouble()).toFloat()
        } else {
            values[0] = atan2(R[1].toDouble(), R[5].toDouble()).toFloat()
            values[1] = asin((-R[9]).toDouble()).toFloat()
            values[2] = atan2((-R[8]).toDouble(), R[10].toDouble()).toFloat()
        }
        return values
    }

    /**
     * Altitude in metres from the pressure [p] and the sea-level pressure [p0] (both hPa, e.g.
     * [PRESSURE_STANDARD_ATMOSPHERE]): 44330 · (1 − (p/p0)^(1/5.255)).
     */
    @JvmStatic
    public fun getAltitude(p0: Float, p: Float): Float =
        ALTITUDE_SCALE_M * (1.0f - (p / p0).toDouble().pow(ALTITUDE_EXPONENT.toDouble()).toFloat())

    /**
     * The angle change from [prevR] to [R] (both device → world, 9 or 16 elements; other lengths
     * read as zeros) as Android angles of prevRᵀ·R, radians, into [angleChange] (3 elements):
     * [0] about z (atan2(rd01, rd11)), [1] about x (asin(−rd21)), [2] about y (atan2(−rd20, rd22)).
     */
    @JvmStatic
    public fun getAngleChange(angleChange: FloatArray, R: FloatArray, prevR: FloatArray) {
        var ri0 = 0f; var ri1 = 0f; var ri2 = 0f; var ri3 = 0f; var ri4 = 0f
        var ri5 = 0f; var ri6 = 0f; var ri7 = 0f; var ri8 = 0f
        var pri0 = 0f; var pri1 = 0f; var pri2 = 0f; var pri3 = 0f; var pri4 = 0f
        var pri5 = 0f; var pri6 = 0f; var pri7 = 0f; var pri8 = 0f
        if (R.size == 9 || R.size == 16) {
            val s = if (R.size == 9) 3 else 4
            ri0 = R[0]; ri1 = R[1]; ri2 = R[2]
            ri3 = R[s]; ri4 = R[s + 1]; ri5 = R[s + 2]
            ri6 = R[2 * s]; ri7 = R[2 * s + 1]; ri8 = R[2 * s + 2]
        }
        if (prevR.size == 9 || prevR.size == 16) {
            val s = if (prevR.size == 9) 3 else 4
            pri0 = prevR[0]; pri1 = prevR[1]; pri2 = prevR[2]
            pri3 = prevR[s]; pri4 = prevR[s + 1]; pri5 = prevR[s + 2]
            pri6 = prevR[2 * s]; pri7 = prevR[2 * s + 1]; pri8 = prevR[2 * s + 2]
        }
        // Only the five elements of rd = prevRᵀ · R that the angles need.
        val rd1 = pri0 * ri1 + pri3 * ri4 + pri6 * ri7
        val rd4 = pri1 * ri1 + pri4 * ri4 + pri7 * ri7
        val rd6 = pri2 * ri0 + pri5 * ri3 + pri8 * ri6
        val rd7 = pri2 * ri1 + pri5 * ri4 + pri8 * ri7
        val rd8 = pri2 * ri2 + pri5 * ri5 + pri8 * ri8
        angleChange[0] = atan2(rd1.toDouble(), rd4.toDouble()).toFloat()
        angleChange[1] = asin((-rd7).toDouble()).toFloat()
        angleChange[2] = atan2((-rd6).toDouble(), rd8.toDouble()).toFloat()
    }

    /**
     * Rotation matrix (device → world) from a rotation vector [rotationVector] as delivered by
     * TYPE_ROTATION_VECTOR / TYPE_GAME_ROTATION_VECTOR (x·sin(θ/2), y·sin(θ/2), z·sin(θ/2),
     * [cos(θ/2), [heading accuracy]]), into [R] (9 or 16 row-major elements; other lengths are
     * left alone). With 3 elements the scalar part is √(1 − |v|²), or 0 when that is negative.
     * The quaternion is not normalised.
     */
    @JvmStatic
    public fun getRotationMatrixFromVector(R: FloatArray, rotationVector: FloatArray) {
        val q1 = rotationVector[0]
        val q2 = rotationVector[1]
        val q3 = rotationVector[2]
        val q0 = if (rotationVector.size >= 4) rotationVector[3] else scalarPart(q1, q2, q3)
        val sqQ1 = 2 * q1 * q1
        val sqQ2 = 2 * q2 * q2
        val sqQ3 = 2 * q3 * q3
        val q1q2 = 2 * q1 * q2
        val q3q0 = 2 * q3 * q0
        val q1q3 = 2 * q1 * q3
        val q2q0 = 2 * q2 * q0
        val q2q3 = 2 * q2 * q3
        val q1q0 = 2 * q1 * q0
        val s = when (R.size) {
            9 -> 3
            16 -> 4
            else -> return
        }
        R[0] = 1 - sqQ2 - sqQ3; R[1] = q1q2 - q3q0; R[2] = q1q3 + q2q0
        R[s] = q1q2 + q3q0; R[s + 1] = 1 - sqQ1 - sqQ3; R[s + 2] = q2q3 - q1q0
        R[2 * s] = q1q3 - q2q0; R[2 * s + 1] = q2q3 + q1q0; R[2 * s + 2] = 1 - sqQ1 - sqQ2
        if (s == 4) {
            R[3] = 0f; R[7] = 0f; R[11] = 0f
            R[12] = 0f; R[13] = 0f; R[14] = 0f
            R[15] = 1f
        }
    }

    /**
     * Quaternion [w, x, y, z] (device → world) from a rotation vector (see
     * [getRotationMatrixFromVector]) into [Q] (4 elements). Not normalised.
     */
    @JvmStatic
    public fun getQuaternionFromVector(Q: FloatArray, rv: FloatArray) {
        Q[0] = if (rv.size >= 4) rv[3] else scalarPart(rv[0], rv[1], rv[2])
        Q[1] = rv[0]
        Q[2] = rv[1]
        Q[3] = rv[2]
    }

    /** √(1 − x² − y² − z²) in AOSP's float arithmetic, 0 when not positive (or NaN). */
    private fun scalarPart(x: Float, y: Float, z: Float): Float {
        val w2 = 1 - x * x - y * y - z * z
        return if (w2 > 0) sqrt(w2.toDouble()).toFloat() else 0f
    }
}
