/*
 * Frames: the world (earth) frames the project meets, and conversions between them.
 *
 *   ENU  x east, y magnetic north, z up: Android's world (getRotationMatrix, rotation vectors).
 *   NWU  x magnetic north, y west, z up: the earth frame of Madgwick's report.
 *   NED  x magnetic north, y east, z down: the aerospace world of seed 003.
 *
 * All are right-handed and share the origin; converting between them is a fixed rotation C with
 * v_to = C · v_from (a change of coordinates of the same physical vector). An orientation q maps
 * sensor → world (v_world = q ⊗ v ⊗ q*), so it converts as q_to = c ⊗ q_from, with c the
 * quaternion of C; e.g. q_ENU = [cos 45°, 0, 0, sin 45°] ⊗ q_NWU. The sensor (device) frame is
 * untouched by these conversions.
 */
package dev.motionfusion.core

/** A world frame, with [toEnu], the matrix taking its coordinates to ENU coordinates (entries 0, ±1). */
public enum class WorldFrame(internal val toEnu: RotationMatrix) {
    /** x east, y magnetic north, z up (Android's world). */
    ENU(RotationMatrix.IDENTITY),

    /** x magnetic north, y west, z up (Madgwick's earth frame): ENU = Rz(+90°) · NWU. */
    NWU(RotationMatrix(0.0, -1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0)),

    /** x magnetic north, y east, z down (aerospace): ENU = (y, x, −z) of NED. */
    NED(RotationMatrix(0.0, 1.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, -1.0));

    /** The matrix C taking coordinates in this frame to coordinates in [to]: v_to = C · v_this. */
    public fun rotationTo(to: WorldFrame): RotationMatrix = to.toEnu.transpose() * toEnu

    /** The unit quaternion c (w ≥ 0) of [rotationTo]: v_to = c ⊗ v_this ⊗ c*, q_to = c ⊗ q_this. */
    public fun quaternionTo(to: WorldFrame): Quaternion = rotationTo(to).toQuaternion()
}

/** The world vector [v] given in frame [from], expressed in frame [to] (exact: a signed permutation). */
public fun convertVector(v: Vector3, from: WorldFrame, to: WorldFrame): Vector3 = from.rotationTo(to) * v

/** The orientation [q] (sensor → [from]) as an orientation sensor → [to]: c ⊗ q. */
public fun convertOrientation(q: Quaternion, from: WorldFrame, to: WorldFrame): Quaternion = from.quaternionTo(to) * q

/** The orientation matrix [m] (sensor → [from]) as a matrix sensor → [to]: C · m. */
public fun convertOrientation(m: RotationMatrix, from: WorldFrame, to: WorldFrame): RotationMatrix =
    from.rotationTo(to) * m
