/*
 * EulerAngles: three angles of an Euler sequence (see EulerSequence.kt for the definitions,
 * ranges and the gimbal-lock choice), with conversions to and from rotation matrices and
 * quaternions, and the named conventions of the seeds:
 *  - AerospaceAngles: yaw ψ, pitch θ, roll φ, the intrinsic Z-Y-X "aerospace sequence" of seed 003,
 *    for a body → NED orientation (body axes x forward, y right, z down);
 *  - rotm2euler / euler2rotm: seed 004's OpenCV/MATLAB form R = Rz(z)·Ry(y)·Rx(x) returning x, y, z.
 * Android's azimuth/pitch/roll (getOrientation) are in sensormanager/AndroidSensorMath.kt.
 * Angles in radians; matrices map body coordinates into the reference frame.
 */
package dev.motionfusion.core

/** Angles [first], [second], [third] (rad) of [sequence] applied as [mode] says (see EulerSequence.kt). */
public data class EulerAngles(
    val first: Double,
    val second: Double,
    val third: Double,
    val sequence: EulerSequence,
    val mode: EulerMode,
) {
    /** The rotation matrix: R_i(first)·R_j(second)·R_k(third) (intrinsic) or R_k·R_j·R_i (extrinsic). */
    public fun toRotationMatrix(): RotationMatrix = compose<RotationMatrix>(RotationMatrix::aboutAxis) { a, b -> a * b }

    /** The unit quaternion of [toRotationMatrix], composed from the three elementary rotations. */
    public fun toQuaternion(): Quaternion =
        compose<Quaternion>({ axis, angle -> Quaternion.fromAxisAngle(UNIT_AXES[axis], angle) }) { a, b -> a * b }

    private inline fun <T> compose(elementary: (Int, Double) -> T, product: (T, T) -> T): T {
        val a = elementary(sequence.i, first)
        val b = elementary(sequence.j, second)
        val c = elementary(sequence.k, third)
        return if (mode == EulerMode.INTRINSIC) product(product(a, b), c) else product(product(c, b), a)
    }

    public companion object {
        private val UNIT_AXES = arrayOf(Vector3.UNIT_X, Vector3.UNIT_Y, Vector3.UNIT_Z)

        /**
         * The angles of [sequence] and [mode] that give [m] (a rotation matrix), in the ranges of
         * EulerSequence.kt; at gimbal lock the third angle is 0.
         */
        public fun fromRotationMatrix(m: RotationMatrix, sequence: EulerSequence, mode: EulerMode): EulerAngles =
            if (mode == EulerMode.INTRINSIC) {
                decomposeEuler(m, sequence.i, sequence.j, sequence.k, zeroLeft = false) { a, b, c ->
                    EulerAngles(a, b, c, sequence, mode)
                }
            } else {
                // R = R_k(third)·R_j(second)·R_i(first): the third angle is the left-most factor.
                decomposeEuler(m, sequence.k, sequence.j, sequence.i, zeroLeft = true) { c, b, a ->
                    EulerAngles(a, b, c, sequence, mode)
                }
            }

        /** The angles of [sequence] and [mode] of the unit quaternion [q] (via its matrix). */
        public fun fromQuaternion(q: Quaternion, sequence: EulerSequence, mode: EulerMode): EulerAngles =
            fromRotationMatrix(q.toRotationMatrix(), sequence, mode)
    }
}

/**
 * The aerospace sequence of seed 003: heading/yaw ψ about z_down, then pitch θ about the new y,
 * then roll φ about the newest x (intrinsic Z-Y-X), radians, describing a body frame (x forward,
 * y right, z down) in a North-East-Down world: R = Rz(ψ)·Ry(θ)·Rx(φ) maps body → NED.
 * Ranges: yaw, roll in [−π, π], pitch in [−π/2, π/2]; at pitch ±π/2 roll is 0.
 */
public data class AerospaceAngles(val yaw: Double, val pitch: Double, val roll: Double) {

    public fun toEulerAngles(): EulerAngles = EulerAngles(yaw, pitch, roll, EulerSequence.ZYX, EulerMode.INTRINSIC)

    /** The body → NED matrix C_b^n of seed 003. */
    public fun toRotationMatrix(): RotationMatrix = toEulerAngles().toRotationMatrix()

    /** The body → NED unit quaternion. */
    public fun toQuaternion(): Quaternion = toEulerAngles().toQuaternion()

    public companion object {
        /** Yaw, pitch, roll of the body → NED matrix [m]. */
        public fun fromRotationMatrix(m: RotationMatrix): AerospaceAngles =
            EulerAngles.fromRotationMatrix(m, EulerSequence.ZYX, EulerMode.INTRINSIC).let {
                AerospaceAngles(it.first, it.second, it.third)
            }

        /** Yaw, pitch, roll of the body → NED unit quaternion [q]. */
        public fun fromQuaternion(q: Quaternion): AerospaceAngles = fromRotationMatrix(q.toRotationMatrix())
    }
}

/**
 * Seed 004's rotationMatrixToEulerAngles (MATLAB rotm2euler with x and z swapped): the angles
 * (x, y, z), radians, with [m] = Rz(z)·Ry(y)·Rx(x), i.e. extrinsic X-Y-Z. Regular case:
 * x = atan2(m21, m22), y = atan2(−m20, sy), z = atan2(m10, m00) with sy = √(m00² + m10²);
 * singular when sy < 1e-6: x = atan2(−m12, m11), y = atan2(−m20, sy), z = 0.
 */
public fun rotm2euler(m: RotationMatrix): Vector3 =
    EulerAngles.fromRotationMatrix(m, EulerSequence.XYZ, EulerMode.EXTRINSIC).let { Vector3(it.first, it.second, it.third) }

/** Seed 004's eulerAnglesToRotationMatrix: Rz(xyz.z)·Ry(xyz.y)·Rx(xyz.x), angles in radians. */
public fun euler2rotm(xyz: Vector3): RotationMatrix =
    EulerAngles(xyz.x, xyz.y, xyz.z, EulerSequence.XYZ, EulerMode.EXTRINSIC).toRotationMatrix()
