package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.random.Random

class QuaternionTest {

    private val rnd = Random(12)
    private val n = 10_000

    @Test
    fun `rotation vector round trip (axis-angle) for angles in 0 to pi`() {
        repeat(n) {
            val axis = Randoms.unitVector(rnd)
            val angle = rnd.nextDouble(0.0, PI)
            val r = axis * angle
            val q = Quaternion.fromRotationVector(r)
            assertEquals(angle, q.angle(), 1e-12)
            assertClose(r, q.toRotationVector(), 1e-12)
            assertSameRotation(Quaternion.fromAxisAngle(axis, angle), q, 1e-15)
        }
        assertClose(Vector3.ZERO, Quaternion.IDENTITY.toRotationVector(), 0.0)
    }

    @Test
    fun `inverse, conjugate and product identities`() {
        repeat(n) {
            val q = Randoms.quaternion(rnd)
            val s = rnd.nextDouble(0.1, 3.0)
            assertSameRotation(Quaternion.IDENTITY, q * q.conjugate(), 1e-15)
            val scaled = q * s
            val p = scaled * scaled.inverse()
            assertEquals(1.0, p.w, 1e-14)
            assertEquals(0.0, p.vector().norm(), 1e-14)
        }
        assertThrows(IllegalArgumentException::class.java) { Quaternion(0.0, 0.0, 0.0, 0.0).inverse() }
    }

    @Test
    fun `slerp hits the endpoints and moves at constant angular rate`() {
        repeat(n) {
            val a = Randoms.quaternion(rnd)
            val b = Randoms.quaternion(rnd)
            val t = rnd.nextDouble()
            val total = a.angleTo(b)
            val m = a.slerp(b, t)
            assertSameRotation(a, a.slerp(b, 0.0), 1e-12)
            assertSameRotation(b, a.slerp(b, 1.0), 1e-12)
            assertEquals(t * total, a.angleTo(m), 1e-6)
            assertEquals((1 - t) * total, m.angleTo(b), 1e-6)
        }
    }
}
