/*
 * AndroidSensorMath: typed, null-safe, validating Kotlin counterparts of SensorManager's math.
 *
 * Frames as in SensorManagerMath.kt: device frame x right, y up along the screen, z out of the
 * screen; world ENU (x east, y magnetic north, z up); a RotationMatrix maps device → ENU.
 * Units: m/s², µT, rad (…Deg only for display), hPa, m.
 *
 * Rough edges of AOSP fixed here: failures are null rather than "untouched output"; wrong
 * lengths and invalid axes throw IllegalArgumentException with a message; asin is clamped so a
 * slightly non-orthonormal matrix cannot give NaN; thresholds are named constants; rotation
 * vectors are normalised; remapping never aliases. getRotationMatrix's free-fall and near-pole
 * decisions and its float results are AOSP's own: those wrappers delegate to SensorManagerMath.
 */
package dev.motionfusion.core.sensormanager

import dev.motionfusion.core.AndroidAngles
import dev.motionfusion.core.Orientations
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.RotationMatrix
import dev.motionfusion.core.Vector3
import kotlin.math.asin
import kotlin.math.atan2
import kotlin.math.pow
import kotlin.math.sqrt

/** Android's azimuth/pitch/roll of the device → ENU matrix [r] (getOrientation with a clamped asin): [Orientations.androidAngles]. */
public fun androidOrientation(r: RotationMatrix): AndroidAngles = Orientations.androidAngles(r)

/**
 * The change of orientation from [previous] to [current] (both device → ENU) as Android angles
 * of previousᵀ · current (getAngleChange), radians.
 */
public fun angleChange(current: RotationMatrix, previous: RotationMatrix): AndroidAngles =
    androidOrientation(previous.transpose() * current)

/**
 * The device → ENU rotation from [gravity] (accelerometer at rest, device frame, m/s², pointing
 * up) and [geomagnetic] (device frame, µT), exactly as getRotationMatrix computes it in float.
 * Null in free fall (|gravity| < 10 % of 9.81 m/s²) or when |geomagnetic × gravity| < 0.1
 * (free fall, or near a magnetic pole where the field is nearly vertical).
 * @throws IllegalArgumentException for non-finite input.
 */
public fun rotationMatrixFrom(gravity: Vector3, geomagnetic: Vector3): RotationMatrix? {
    val r = FloatArray(9)
    if (!rotationAndInclination(gravity, geomagnetic, r, null)) return null
    return RotationMatrix.fromRowMajor(r)
}

/**
 * The geomagnetic inclination (dip) angle, radians, positive when the field points below the
 * horizon, from [gravity] and [geomagnetic] as in [rotationMatrixFrom] (getRotationMatrix's I,
 * then getInclination). Null where [rotationMatrixFrom] is null.
 */
public fun inclinationFrom(gravity: Vector3, geomagnetic: Vector3): Double? {
    val i = FloatArray(9)
    if (!rotationAndInclination(gravity, geomagnetic, null, i)) return null
    return atan2(i[5].toDouble(), i[4].toDouble())
}

private fun rotationAndInclination(gravity: Vector3, geomagnetic: Vector3, r: FloatArray?, i: FloatArray?): Boolean {
    require(gravity.isFinite()) { "gravity must be finite, got $gravity" }
    require(geomagnetic.isFinite()) { "geomagnetic must be finite, got $geomagnetic" }
    return SensorManagerMath.getRotationMatrix(r, i, gravity.toFloatArray(), geomagnetic.toFloatArray())
}

/** An axis argument of [remapCoordinateSystem], with its AOSP constant [aospValue]. */
public enum class RemapAxis(public val aospValue: Int, internal val index: Int, internal val sign: Double) {
    X(SensorManagerMath.AXIS_X, 0, 1.0),
    Y(SensorManagerMath.AXIS_Y, 1, 1.0),
    Z(SensorManagerMath.AXIS_Z, 2, 1.0),
    MINUS_X(SensorManagerMath.AXIS_MINUS_X, 0, -1.0),
    MINUS_Y(SensorManagerMath.AXIS_MINUS_Y, 1, -1.0),
    MINUS_Z(SensorManagerMath.AXIS_MINUS_Z, 2, -1.0),
}

/**
 * remapCoordinateSystem on a typed matrix: the rotation [r] (device → world) rewritten for a
 * new device frame in which the original x axis lies along the new axis [x] and the original y
 * axis along the new axis [y] (AOSP semantics: new coordinates = S · old coordinates and
 * out = r · Sᵀ, with S = [x | y | x × y] as signed unit vectors).
 * @throws IllegalArgumentException when [x] and [y] lie along the same device axis.
 */
public fun remapCoordinateSystem(r: RotationMatrix, x: RemapAxis, y: RemapAxis): RotationMatrix {
    require(x.index != y.index) { "remap axes must differ, got $x and $y" }
    fun unit(a: RemapAxis) = Vector3(
        if (a.index == 0) a.sign else 0.0,
        if (a.index == 1) a.sign else 0.0,
        if (a.index == 2) a.sign else 0.0,
    )
    val ex = unit(x)
    val ey = unit(y)
    val ez = ex cross ey
    val sT = RotationMatrix(ex.x, ex.y, ex.z, ey.x, ey.y, ey.z, ez.x, ez.y, ez.z)
    return r * sT
}

/**
 * [r] (device → world) remapped for the display rotation [displayRotation] (Surface.ROTATION_0,
 * _90, _180, _270 = 0, 1, 2, 3), so that angles refer to the screen as the user sees it:
 * 0 → unchanged, 1 → (Y, −X), 2 → (−X, −Y), 3 → (−Y, X).
 * @throws IllegalArgumentException for a value outside 0..3 (e.g. degrees passed by mistake).
 */
public fun remapForDisplayRotation(r: RotationMatrix, displayRotation: Int): RotationMatrix = when (displayRotation) {
    0 -> r
    1 -> remapCoordinateSystem(r, RemapAxis.Y, RemapAxis.MINUS_X)
    2 -> remapCoordinateSystem(r, RemapAxis.MINUS_X, RemapAxis.MINUS_Y)
    3 -> remapCoordinateSystem(r, RemapAxis.MINUS_Y, RemapAxis.X)
    else -> throw IllegalArgumentException(
        "displayRotation must be Surface.ROTATION_0..ROTATION_270 (0..3), got $displayRotation",
    )
}

/**
 * The unit quaternion (device → world: ENU for TYPE_ROTATION_VECTOR) of a rotation vector event
 * [values] (3 to 5 elements: x·sin(θ/2), y·sin(θ/2), z·sin(θ/2), [cos(θ/2)], [heading accuracy]).
 * With 3 elements w = √(1 − |v|²), 0 when negative. Normalised (AOSP does not normalise).
 * @throws IllegalArgumentException for another length or a zero or non-finite quaternion.
 */
public fun quaternionFromRotationVector(values: FloatArray): Quaternion {
    require(values.size in 3..5) { "a rotation vector has 3 to 5 values, got ${values.size}" }
    val x = values[0].toDouble()
    val y = values[1].toDouble()
    val z = values[2].toDouble()
    val w = if (values.size >= 4) values[3].toDouble() else sqrt((1.0 - x * x - y * y - z * z).coerceAtLeast(0.0))
    return Quaternion(w, x, y, z).normalized()
}

/** The orthonormal device → world matrix of a rotation vector event (see [quaternionFromRotationVector]). */
public fun rotationMatrixFromRotationVector(values: FloatArray): RotationMatrix =
    quaternionFromRotationVector(values).toRotationMatrix()

/**
 * Altitude in metres above the level where the pressure is [seaLevelPressureHpa], from the
 * pressure [pressureHpa] (both hPa; the default is the standard atmosphere, 1013.25 hPa), by the barometric formula of getAltitude:
 * 44330 · (1 − (p/p0)^(1/5.255)).
 * @throws IllegalArgumentException unless both pressures are finite and positive.
 */
public fun altitudeM(
    pressureHpa: Double,
    seaLevelPressureHpa: Double = SensorManagerMath.PRESSURE_STANDARD_ATMOSPHERE.toDouble(),
): Double {
    require(pressureHpa > 0.0 && pressureHpa.isFinite()) { "pressure must be positive and finite, got $pressureHpa hPa" }
    require(seaLevelPressureHpa > 0.0 && seaLevelPressureHpa.isFinite()) {
        "sea-level pressure must be positive and finite, got $seaLevelPressureHpa hPa"
    }
    return BAROMETRIC_SCALE_M * (1.0 - (pressureHpa / seaLevelPressureHpa).pow(1.0 / BAROMETRIC_EXPONENT_DENOMINATOR))
}

private const val BAROMETRIC_SCALE_M = 44330.0
private const val BAROMETRIC_EXPONENT_DENOMINATOR = 5.255
