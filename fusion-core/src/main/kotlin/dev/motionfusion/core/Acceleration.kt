/*
 * Acceleration (seed 003): what an accelerometer measures and how to remove gravity from it.
 *
 * An accelerometer measures specific force f = a − g⃗ (m/s², sensor frame): the non-gravitational
 * force per unit mass. At rest it reads +g along the up direction (9.81 on z when the device
 * lies screen up); in free fall it reads 0. Following Android (TYPE_GRAVITY,
 * TYPE_LINEAR_ACCELERATION), "gravity" below is that at-rest reading, pointing UP, magnitude g,
 * and linear acceleration = specific force − gravity = the kinematic acceleration a.
 *
 * The orientation q maps sensor → a z-up world (ENU, or NWU: only "up" matters here);
 * see docs/CONVENTIONS.md. Units: m/s²; g defaults to [STANDARD_GRAVITY].
 */
package dev.motionfusion.core

/** Standard gravity g₀ = 9.80665 m/s² (exact by definition). */
public const val STANDARD_GRAVITY: Double = 9.80665

/** Gravity (the at-rest accelerometer reading, pointing up, magnitude [g] m/s²) in the sensor frame: q* ⊗ [0,0,g] ⊗ q. */
public fun gravityInSensorFrame(orientation: Quaternion, g: Double = STANDARD_GRAVITY): Vector3 =
    orientation.inverseRotate(Vector3(0.0, 0.0, g))

/** Linear acceleration in the sensor frame, m/s²: [specificForce] (sensor frame) minus [gravityInSensorFrame]. */
public fun linearAccelerationInSensorFrame(
    specificForce: Vector3, orientation: Quaternion, g: Double = STANDARD_GRAVITY,
): Vector3 = specificForce - gravityInSensorFrame(orientation, g)

/**
 * Linear acceleration in the world frame of [orientation] (ENU when it is sensor → ENU), m/s²:
 * q ⊗ f ⊗ q* − [0, 0, g]. At rest this is zero; its z is the vertical acceleration, up positive.
 */
public fun linearAccelerationInEarthFrame(
    specificForce: Vector3, orientation: Quaternion, g: Double = STANDARD_GRAVITY,
): Vector3 = orientation.rotate(specificForce) - Vector3(0.0, 0.0, g)

/**
 * Linear acceleration in the yaw-aligned horizontal frame, m/s²: the world frame turned about
 * the vertical so that y points along the device's y axis projected on the ground (forward),
 * x to its right, z up; the device frame with its pitch and roll taken out (seed 003's
 * "horizontal frame", with the phone's y axis as the heading). v_H = Rz(ψ) · v_world with
 * ψ = atan2(R01, R11) the heading of the device's y axis (Android's azimuth when the world is
 * ENU). When the device's y axis is vertical the heading is undefined and ψ = atan2(0, 0) = 0.
 */
public fun linearAccelerationInHorizontalFrame(
    specificForce: Vector3, orientation: Quaternion, g: Double = STANDARD_GRAVITY,
): Vector3 {
    val heading = Orientations.azimuth(orientation.toDoubleArray())
    return RotationMatrix.aboutAxis(2, heading) * linearAccelerationInEarthFrame(specificForce, orientation, g)
}
