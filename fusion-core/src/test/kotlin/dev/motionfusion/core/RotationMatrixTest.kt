package dev.motionfusion.core

import android.hardware.SensorManager
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.acos
import kotlin.random.Random

class RotationMatrixTest {

    private val rnd = Random(11)
    private val n = 10_000

    @Test
    fun `matrices of random quaternions are orthonormal with determinant 1`() {
        repeat(n) {
            val m = Randoms.quaternion(rnd).toRotationMatrix()
            assertClose(RotationMatrix.IDENTITY, m.transpose() * m, 1e-14)
            assertEquals(1.0, m.determinant(), 1e-14)
            assertTrue(m.isRotationMatrix())
        }
    }

    @Test
    fun `q and -q give the same matrix, and the matrix rotates like the quaternion`() {
        repeat(n) {
            val q = Randoms.quaternion(rnd)
            val v = Randoms.vector(rnd, 10.0)
            assertClose(q.toRotationMatrix(), (-q).toRotationMatrix(), 1e-15)
            assertClose(q.rotate(v), q.toRotationMatrix() * v, 1e-13)
            assertClose(q.inverseRotate(v), q.toRotationMatrix().transpose() * v, 1e-13)
        }
    }

    @Test
    fun `matrix to quaternion round trip for all rotations, including near and at 180 degrees`() {
        repeat(n) {
            val q = when (it % 3) {
                0 -> Randoms.quaternion(rnd)
                // rotation angle within 1e-9..1e-3 rad of π: w tiny
                1 -> Quaternion.fromAxisAngle(Randoms.unitVector(rnd), PI - Math.pow(10.0, rnd.nextDouble(-9.0, -3.0)))
                else -> Quaternion.fromAxisAngle(Randoms.unitVector(rnd), PI) // exactly π (w = 6e-17)
            }
            val back = q.toRotationMatrix().toQuaternion()
            assertSameRotation(q, back, 1e-14)
            assertTrue(back.w >= 0.0)
            assertEquals(1.0, back.norm(), 1e-15)
            // Componentwise, not only up to the norm: the axis of a 180° rotation is recovered.
            val c = q.canonical()
            for ((e, a) in c.toDoubleArray().zip(back.toDoubleArray())) {
                if (c.w > 1e-9) assertEquals(e, a, 1e-13) else assertEquals(abs(e), abs(a), 1e-13)
            }
        }
    }

    @Test
    fun `composition of quaternions matches the matrix product`() {
        repeat(n) {
            val a = Randoms.quaternion(rnd)
            val b = Randoms.quaternion(rnd)
            assertClose(a.toRotationMatrix() * b.toRotationMatrix(), (a * b).toRotationMatrix(), 1e-14)
        }
    }

    @Test
    fun `angleTo equals the angle of the relative rotation matrix`() {
        repeat(n) {
            val a = Randoms.quaternion(rnd)
            val b = Randoms.quaternion(rnd)
            val rel = a.toRotationMatrix().transpose() * b.toRotationMatrix()
            val trace = rel.m00 + rel.m11 + rel.m22
            assertEquals(acos(((trace - 1) / 2).coerceIn(-1.0, 1.0)), a.angleTo(b), 1e-6)
        }
    }

    @Test
    fun `elementary rotations follow the right-hand rule of seed 004`() {
        val a = 0.3
        assertClose(Vector3(0.0, kotlin.math.cos(a), kotlin.math.sin(a)), RotationMatrix.aboutAxis(0, a) * Vector3.UNIT_Y, 1e-15)
        assertClose(Vector3(kotlin.math.sin(a), 0.0, kotlin.math.cos(a)), RotationMatrix.aboutAxis(1, a) * Vector3.UNIT_Z, 1e-15)
        assertClose(Vector3(kotlin.math.cos(a), kotlin.math.sin(a), 0.0), RotationMatrix.aboutAxis(2, a) * Vector3.UNIT_X, 1e-15)
        repeat(3) { axis ->
            val unit = arrayOf(Vector3.UNIT_X, Vector3.UNIT_Y, Vector3.UNIT_Z)[axis]
            assertClose(Quaternion.fromAxisAngle(unit, a).toRotationMatrix(), RotationMatrix.aboutAxis(axis, a), 1e-15)
        }
        assertThrows(IllegalArgumentException::class.java) { RotationMatrix.aboutAxis(3, a) }
    }

    @Test
    fun `isRotationMatrix rejects reflections, scaling and skew beyond the tolerance`() {
        val m = Randoms.quaternion(rnd).toRotationMatrix()
        val reflected = RotationMatrix(-m.m00, m.m01, m.m02, -m.m10, m.m11, m.m12, -m.m20, m.m21, m.m22)
        assertFalse(reflected.isRotationMatrix())
        val scaled = RotationMatrix(m.m00 * 1.001, m.m01, m.m02, m.m10 * 1.001, m.m11, m.m12, m.m20 * 1.001, m.m21, m.m22)
        assertFalse(scaled.isRotationMatrix())
        assertTrue(scaled.isRotationMatrix(tolerance = 1e-2))
    }

    @Test
    fun `float layouts of 9 and 16 elements round trip and match AOSP's rotation vector matrix`() {
        repeat(1_000) {
            val q = Randoms.quaternion(rnd).canonical()
            val m = q.toRotationMatrix()
            for (size in intArrayOf(9, 16)) {
                val f = m.toFloatArray(size)
                assertClose(m, RotationMatrix.fromRowMajor(f), 1e-7)
                // Independent oracle: AOSP's own quaternion → matrix formula, in float.
                val aosp = FloatArray(size)
                SensorManager.getRotationMatrixFromVector(aosp, floatArrayOf(q.x.toFloat(), q.y.toFloat(), q.z.toFloat(), q.w.toFloat()))
                for (i in 0 until size) assertEquals(aosp[i], f[i], 1e-6f) { "element $i of $size" }
                // The allocation-free path agrees with the immutable one.
                val viaArrays = FloatArray(size)
                RotationArrays.quaternionToRotationMatrix(q.toDoubleArray(), viaArrays)
                for (i in 0 until size) assertEquals(f[i], viaArrays[i], 1e-7f)
                val qd = DoubleArray(4)
                RotationArrays.rotationMatrixToQuaternion(f, qd)
                assertSameRotation(q, Quaternion(qd[0], qd[1], qd[2], qd[3]), 1e-6)
            }
        }
        assertThrows(IllegalArgumentException::class.java) { RotationMatrix.fromRowMajor(FloatArray(12)) }
        assertThrows(IllegalArgumentException::class.java) { RotationArrays.quaternionToRotationMatrix(DoubleArray(3), FloatArray(9)) }
        assertThrows(IllegalArgumentException::class.java) { RotationArrays.rotationMatrixToQuaternion(FloatArray(10), DoubleArray(4)) }
    }
}
