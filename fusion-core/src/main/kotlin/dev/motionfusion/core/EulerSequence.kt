/*
 * EulerSequence: the 12 Euler angle sequences and whether their axes are body-fixed (intrinsic)
 * or space-fixed (extrinsic), and the decomposition of a rotation matrix into them.
 *
 * Angles in radians; axes 0 = x, 1 = y, 2 = z of the frame the rotation acts in; positive
 * rotation by the right-hand rule. For the sequence (i, j, k) and angles (a, b, c):
 *   INTRINSIC: rotate by a about i, then by b about the new j, then by c about the newest k:
 *              R = R_i(a) · R_j(b) · R_k(c)
 *   EXTRINSIC: rotate by a about the fixed i, then b about the fixed j, then c about the fixed k:
 *              R = R_k(c) · R_j(b) · R_i(a)
 * with R_x, R_y, R_z the elementary rotations of seed 004. Used as an orientation, R maps body
 * (sensor) coordinates into the reference (world) frame.
 *
 * Ranges returned: first and third angle in [−π, π]; second angle in [−π/2, π/2] for Tait-Bryan
 * sequences and [0, π] for proper Euler sequences.
 * Gimbal lock (second angle at ±π/2 for Tait-Bryan, 0 or π for proper Euler; detected when
 * cos or sin of it is below [GIMBAL_LOCK_THRESHOLD], seed 004's 1e-6): only the sum or difference
 * of the first and third angles is defined; the THIRD angle (the last rotation applied) is set to
 * 0 and the first carries the whole rotation, as seed 004's rotm2euler does (its z is the third
 * angle of extrinsic X-Y-Z).
 */
package dev.motionfusion.core

import kotlin.math.atan2
import kotlin.math.sqrt

/** The 12 Euler sequences: 6 Tait-Bryan (three distinct axes) and 6 proper Euler (first = third). */
public enum class EulerSequence(internal val i: Int, internal val j: Int, internal val k: Int) {
    XYZ(0, 1, 2), XZY(0, 2, 1), YXZ(1, 0, 2), YZX(1, 2, 0), ZXY(2, 0, 1), ZYX(2, 1, 0),
    XYX(0, 1, 0), XZX(0, 2, 0), YXY(1, 0, 1), YZY(1, 2, 1), ZXZ(2, 0, 2), ZYZ(2, 1, 2);

    /** True for proper Euler sequences (first axis = third axis), false for Tait-Bryan. */
    public val isProperEuler: Boolean get() = i == k
}

/** Whether the axes of an Euler sequence move with the body (intrinsic) or stay fixed (extrinsic). */
public enum class EulerMode { INTRINSIC, EXTRINSIC }

/** cos(second angle) (Tait-Bryan) or sin(second angle) (proper) below this is gimbal lock. */
public const val GIMBAL_LOCK_THRESHOLD: Double = 1e-6

/**
 * Decomposes [m] = R_p(α) · R_q(β) · R_r(γ) and hands (α, β, γ) to [build]. At gimbal lock α is
 * set to 0 when [zeroLeft], else γ.
 *
 * Derivation (Tait-Bryan, p, q, r distinct, ε = +1 when (p, q, r) is cyclic, −1 otherwise):
 * m[p][r] = ε sin β, m[q][r] = −ε sin α cos β, m[r][r] = cos α cos β, m[p][q] = −ε cos β sin γ,
 * m[p][p] = cos β cos γ, and cos β = √(m[r][r]² + m[q][r]²) (seed 004's sy).
 * Proper Euler (p = r, s the remaining axis, ε the parity of (p, q, s)): m[p][p] = cos β,
 * m[q][p] = sin α sin β, m[s][p] = −ε cos α sin β, m[p][q] = sin β sin γ, m[p][s] = ε sin β cos γ.
 * At the lock, m reduces to R_p(α)·R_q(β) or R_q(β)·R_r(γ), whose column q (resp. row q) holds
 * the remaining angle alone.
 */
internal inline fun <T> decomposeEuler(
    m: RotationMatrix, p: Int, q: Int, r: Int, zeroLeft: Boolean,
    build: (Double, Double, Double) -> T,
): T {
    val eps = if ((q - p + 3) % 3 == 1) 1.0 else -1.0
    if (p != r) {
        val cosB = sqrt(m[r, r] * m[r, r] + m[q, r] * m[q, r])
        val beta = atan2(eps * m[p, r], cosB)
        return when {
            cosB >= GIMBAL_LOCK_THRESHOLD ->
                build(atan2(-eps * m[q, r], m[r, r]), beta, atan2(-eps * m[p, q], m[p, p]))
            zeroLeft -> build(0.0, beta, atan2(eps * m[q, p], m[q, q]))
            else -> build(atan2(eps * m[r, q], m[q, q]), beta, 0.0)
        }
    }
    val s = 3 - p - q
    val sinB = sqrt(m[q, p] * m[q, p] + m[s, p] * m[s, p])
    val beta = atan2(sinB, m[p, p])
    return when {
        sinB >= GIMBAL_LOCK_THRESHOLD ->
            build(atan2(m[q, p], -eps * m[s, p]), beta, atan2(m[p, q], eps * m[p, s]))
        zeroLeft -> build(0.0, beta, atan2(-eps * m[q, s], m[q, q]))
        else -> build(atan2(eps * m[s, q], m[q, q]), beta, 0.0)
    }
}
