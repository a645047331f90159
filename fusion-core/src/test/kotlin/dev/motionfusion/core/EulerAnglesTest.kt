package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.params.ParameterizedTest
import org.junit.jupiter.params.provider.Arguments
import org.junit.jupiter.params.provider.MethodSource
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.math.atan2
import kotlin.math.cos
import kotlin.math.sin
import kotlin.math.sqrt
import kotlin.random.Random

class EulerAnglesTest {

    private val n = 2_000

    /** A second angle at least [margin] away from gimbal lock, inside the returned range. */
    private fun regularSecond(rnd: Random, sequence: EulerSequence, margin: Double) =
        if (sequence.isProperEuler) rnd.nextDouble(margin, PI - margin) else rnd.nextDouble(-PI / 2 + margin, PI / 2 - margin)

    private fun angle(rnd: Random) = rnd.nextDouble(-PI, PI)

    @ParameterizedTest
    @MethodSource("allConventions")
    fun `angles to matrix and quaternion and back, away from gimbal lock`(sequence: EulerSequence, mode: EulerMode) {
        val rnd = Random(sequence.ordinal * 2 + mode.ordinal)
        repeat(n) {
            val e = EulerAngles(angle(rnd), regularSecond(rnd, sequence, 1e-3), angle(rnd), sequence, mode)
            val m = e.toRotationMatrix()
            assertTrue(m.isRotationMatrix(1e-12))
            assertClose(m, e.toQuaternion().toRotationMatrix(), 1e-14)
            for (back in listOf(EulerAngles.fromRotationMatrix(m, sequence, mode), EulerAngles.fromQuaternion(e.toQuaternion(), sequence, mode))) {
                // 1e-3 from the lock, angle errors grow like 1/cos β: 1e-16 / 1e-3.
                assertEquals(e.first, back.first, 1e-11) { "$e -> $back" }
                assertEquals(e.second, back.second, 1e-11) { "$e -> $back" }
                assertEquals(e.third, back.third, 1e-11) { "$e -> $back" }
            }
        }
    }

    @ParameterizedTest
    @MethodSource("allConventions")
    fun `random rotations decompose into the documented ranges and recompose exactly`(sequence: EulerSequence, mode: EulerMode) {
        val rnd = Random(100 + sequence.ordinal * 2 + mode.ordinal)
        repeat(n) {
            val q = Randoms.quaternion(rnd)
            val e = EulerAngles.fromQuaternion(q, sequence, mode)
            assertTrue(e.first in -PI..PI && e.third in -PI..PI)
            assertTrue(if (sequence.isProperEuler) e.second in 0.0..PI else e.second in -PI / 2..PI / 2)
            assertSameRotation(q, e.toQuaternion(), 1e-13)
        }
    }

    @ParameterizedTest
    @MethodSource("allConventions")
    fun `at gimbal lock the third angle is 0 and the rotation is preserved`(sequence: EulerSequence, mode: EulerMode) {
        val rnd = Random(200 + sequence.ordinal * 2 + mode.ordinal)
        val locks = if (sequence.isProperEuler) listOf(0.0, PI) else listOf(PI / 2, -PI / 2)
        repeat(n) {
            // Exactly at the lock, or within 1e-8 rad of it (well inside the 1e-6 threshold).
            val second = locks[it % 2] + if (it % 3 == 0) 0.0 else rnd.nextDouble(-1e-8, 1e-8)
            val e = EulerAngles(angle(rnd), second, angle(rnd), sequence, mode)
            val m = e.toRotationMatrix()
            val back = EulerAngles.fromRotationMatrix(m, sequence, mode)
            assertEquals(0.0, back.third, 0.0) { "$e -> $back" }
            assertClose(m, back.toRotationMatrix(), 1e-7) { "$e -> $back" }
        }
    }

    @ParameterizedTest
    @MethodSource("allConventions")
    fun `intrinsic rotates about moved axes, extrinsic about fixed axes`(sequence: EulerSequence, mode: EulerMode) {
        // Independent of the composition code: build the rotation step by step with axis-angle
        // quaternions, rotating about the body's current axis (intrinsic) or the fixed axis.
        val rnd = Random(300 + sequence.ordinal)
        val units = arrayOf(Vector3.UNIT_X, Vector3.UNIT_Y, Vector3.UNIT_Z)
        repeat(200) {
            val angles = doubleArrayOf(angle(rnd), angle(rnd), angle(rnd))
            var q = Quaternion.IDENTITY
            for ((axis, a) in intArrayOf(sequence.i, sequence.j, sequence.k).zip(angles.toTypedArray())) {
                val about = if (mode == EulerMode.INTRINSIC) q.rotate(units[axis]) else units[axis]
                q = Quaternion.fromAxisAngle(about, a) * q
            }
            val e = EulerAngles(angles[0], angles[1], angles[2], sequence, mode)
            assertSameRotation(q, e.toQuaternion(), 1e-13)
        }
    }

    @Test
    fun `aerospace Z-Y-X angles match seed 003's direction cosine matrix and quaternion formulas`() {
        val rnd = Random(400)
        repeat(n) {
            val psi = angle(rnd)
            val theta = rnd.nextDouble(-PI / 2 + 1e-3, PI / 2 - 1e-3)
            val phi = angle(rnd)
            val (c, s) = Pair(::cos, ::sin)
            // Seed 003: C_b^n in terms of ψ, θ, φ.
            val cbn = RotationMatrix(
                c(theta) * c(psi), -c(phi) * s(psi) + s(phi) * s(theta) * c(psi), s(phi) * s(psi) + c(phi) * s(theta) * c(psi),
                c(theta) * s(psi), c(phi) * c(psi) + s(phi) * s(theta) * s(psi), -s(phi) * c(psi) + c(phi) * s(theta) * s(psi),
                -s(theta), s(phi) * c(theta), c(phi) * c(theta),
            )
            // Seed 003: q_123(φ, θ, ψ).
            val (cf, sf, ct, st, cp, sp) = listOf(c(phi / 2), s(phi / 2), c(theta / 2), s(theta / 2), c(psi / 2), s(psi / 2))
            val q = Quaternion(
                cf * ct * cp + sf * st * sp,
                -cf * st * sp + ct * cp * sf,
                cf * cp * st + sf * ct * sp,
                cf * ct * sp - sf * cp * st,
            )
            val angles = AerospaceAngles(psi, theta, phi)
            assertClose(cbn, angles.toRotationMatrix(), 1e-14)
            assertSameRotation(q, angles.toQuaternion(), 1e-14)
            val back = AerospaceAngles.fromQuaternion(q)
            assertEquals(psi, back.yaw, 1e-10)
            assertEquals(theta, back.pitch, 1e-10)
            assertEquals(phi, back.roll, 1e-10)
        }
    }

    @Test
    fun `seed 004's example - two angle triples give the same matrix and rotm2euler returns the documented one`() {
        // Seed 004 prints [0.1920, 2.3736, 1.170] rad beside [11, 136, 64] degrees; 64° is 1.1170 rad,
        // so "1.170" lost a digit: with 1.170 the matrices differ by about 0.035, with 1.1170
        // (and in degrees) they agree to the rounding of the printed values.
        val documented = Vector3(-2.9496, 0.7679, -2.0246)
        val a = euler2rotm(Vector3(0.1920, 2.3736, 1.1170))
        val b = euler2rotm(documented)
        assertClose(a, b, 2e-4)
        val typo = euler2rotm(Vector3(0.1920, 2.3736, 1.170))
        assertTrue((0 until 9).maxOf { kotlin.math.abs(typo.toDoubleArray()[it] - b.toDoubleArray()[it]) } > 0.01)
        val deg = { x: Double, y: Double, z: Double -> euler2rotm(Vector3(Math.toRadians(x), Math.toRadians(y), Math.toRadians(z))) }
        assertClose(deg(11.0, 136.0, 64.0), deg(-169.0, 44.0, -116.0), 1e-12)
        // y = 2.3736 lies outside rotm2euler's [−π/2, π/2], so it returns the other triple.
        assertClose(documented, rotm2euler(a), 2e-4)
        assertClose(documented, rotm2euler(b), 1e-12)
    }

    @Test
    fun `rotm2euler equals seed 004's rotationMatrixToEulerAngles, regular and singular`() {
        val rnd = Random(500)
        repeat(n) {
            val m = if (it % 4 == 0) {
                euler2rotm(Vector3(angle(rnd), (if (rnd.nextBoolean()) PI else -PI) / 2 + rnd.nextDouble(-1e-7, 1e-7), angle(rnd)))
            } else {
                Randoms.quaternion(rnd).toRotationMatrix()
            }
            assertClose(seed004(m), rotm2euler(m), 1e-15)
        }
    }

    /** Seed 004's rotationMatrixToEulerAngles, transcribed in double as the oracle. */
    private fun seed004(r: RotationMatrix): Vector3 {
        val sy = sqrt(r.m00 * r.m00 + r.m10 * r.m10)
        return if (sy >= 1e-6) {
            Vector3(atan2(r.m21, r.m22), atan2(-r.m20, sy), atan2(r.m10, r.m00))
        } else {
            Vector3(atan2(-r.m12, r.m11), atan2(-r.m20, sy), 0.0)
        }
    }

    private operator fun <T> List<T>.component6() = this[5]

    companion object {
        @JvmStatic
        fun allConventions(): List<Arguments> =
            EulerSequence.entries.flatMap { s -> EulerMode.entries.map { m -> Arguments.of(s, m) } }
    }
}
