package dev.motionfusion.core.sensormanager

import android.hardware.SensorManager
import dev.motionfusion.core.EulerAngles
import dev.motionfusion.core.EulerMode
import dev.motionfusion.core.EulerSequence
import dev.motionfusion.core.Randoms
import dev.motionfusion.core.RotationMatrix
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.assertClose
import dev.motionfusion.core.assertSameRotation
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import kotlin.math.PI
import kotlin.random.Random

/** The typed wrappers against the real AOSP SensorManager (with tolerances: they compute in double). */
class AndroidSensorMathTest {

    private val rnd = Random(41)
    private val n = 10_000

    @Test
    fun `rotationMatrixFrom and inclinationFrom equal getRotationMatrix and getInclination, null where it fails`() {
        var nulls = 0
        repeat(n) {
            val gravity = Randoms.vector(rnd, if (it % 3 == 0) 1.5 else 12.0)
            val field = if (it % 5 == 0) gravity * 2.0 + Randoms.vector(rnd, 0.02) else Randoms.vector(rnd, 60.0)
            val r = FloatArray(9)
            val i = FloatArray(9)
            val ok = SensorManager.getRotationMatrix(r, i, gravity.toFloatArray(), field.toFloatArray())
            val typed = rotationMatrixFrom(gravity, field)
            val inclination = inclinationFrom(gravity, field)
            if (!ok) {
                nulls++
                assertNull(typed)
                assertNull(inclination)
            } else {
                assertEquals(RotationMatrix.fromRowMajor(r), typed)
                assertEquals(SensorManager.getInclination(i).toDouble(), inclination!!, 1e-6)
            }
        }
        assertTrue(nulls in n / 20..n / 2, "nulls $nulls")
        assertThrows<IllegalArgumentException> { rotationMatrixFrom(Vector3(Double.NaN, 0.0, 9.8), Vector3(0.0, 20.0, -40.0)) }
    }

    @Test
    fun `androidOrientation matches getOrientation and AndroidAngles rebuilds the matrix`() {
        repeat(n) {
            val m = Randoms.quaternion(rnd).toRotationMatrix()
            val expected = SensorManager.getOrientation(m.toFloatArray(), FloatArray(3))
            val angles = androidOrientation(m)
            assertEquals(expected[0].toDouble(), angles.azimuth, 1e-5)
            assertEquals(expected[1].toDouble(), angles.pitch, 1e-5)
            assertEquals(expected[2].toDouble(), angles.roll, 1e-5)
            assertClose(m, angles.toRotationMatrix(), 1e-12)
            // They are intrinsic Z-X-Y angles (−azimuth, −pitch, roll).
            val zxy = EulerAngles.fromRotationMatrix(m, EulerSequence.ZXY, EulerMode.INTRINSIC)
            assertEquals(-zxy.first, angles.azimuth, 1e-9)
            assertEquals(-zxy.second, angles.pitch, 1e-9)
            assertEquals(zxy.third, angles.roll, 1e-9)
        }
    }

    @Test
    fun `androidOrientation clamps asin where getOrientation gives NaN`() {
        val slightlyOff = RotationMatrix(1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, -1.0000001, 0.0)
        assertTrue(SensorManager.getOrientation(slightlyOff.toFloatArray(), FloatArray(3))[1].isNaN())
        assertEquals(PI / 2, androidOrientation(slightlyOff).pitch, 0.0)
    }

    @Test
    fun `angleChange matches getAngleChange`() {
        repeat(n) {
            val prev = Randoms.quaternion(rnd).toRotationMatrix()
            val cur = Randoms.quaternion(rnd).toRotationMatrix()
            val expected = FloatArray(3).also { SensorManager.getAngleChange(it, cur.toFloatArray(), prev.toFloatArray()) }
            val change = angleChange(cur, prev)
            assertEquals(expected[0].toDouble(), change.azimuth, 1e-5)
            assertEquals(expected[1].toDouble(), change.pitch, 1e-5)
            assertEquals(expected[2].toDouble(), change.roll, 1e-5)
        }
    }

    @Test
    fun `remapCoordinateSystem matches AOSP for all 24 valid axis pairs and rejects equal axes`() {
        repeat(200) {
            val m = Randoms.quaternion(rnd).toRotationMatrix()
            for (x in RemapAxis.entries) for (y in RemapAxis.entries) {
                val out = FloatArray(9)
                val ok = SensorManager.remapCoordinateSystem(m.toFloatArray(), x.aospValue, y.aospValue, out)
                if (ok) {
                    val typed = remapCoordinateSystem(m, x, y)
                    assertClose(RotationMatrix.fromRowMajor(out), typed, 1e-7) { "$x $y" }
                    assertTrue(typed.isRotationMatrix(1e-12))
                } else {
                    assertThrows<IllegalArgumentException> { remapCoordinateSystem(m, x, y) }
                }
            }
        }
    }

    @Test
    fun `display rotation remap uses Android's documented axes`() {
        val pairs = mapOf(
            1 to (SensorManager.AXIS_Y to SensorManager.AXIS_MINUS_X),
            2 to (SensorManager.AXIS_MINUS_X to SensorManager.AXIS_MINUS_Y),
            3 to (SensorManager.AXIS_MINUS_Y to SensorManager.AXIS_X),
        )
        repeat(1_000) {
            val m = Randoms.quaternion(rnd).toRotationMatrix()
            assertEquals(m, remapForDisplayRotation(m, 0))
            for ((rotation, axes) in pairs) {
                val out = FloatArray(9)
                assertTrue(SensorManager.remapCoordinateSystem(m.toFloatArray(), axes.first, axes.second, out))
                assertClose(RotationMatrix.fromRowMajor(out), remapForDisplayRotation(m, rotation), 1e-7)
            }
        }
        val e = assertThrows<IllegalArgumentException> { remapForDisplayRotation(RotationMatrix.IDENTITY, 90) }
        assertTrue(e.message!!.contains("0..3"))
    }

    @Test
    fun `rotation vectors of 3, 4 and 5 values give AOSP's quaternion, normalised`() {
        repeat(n) {
            val rv = SensorManagerMathDifferentialTest.rotationVector(rnd, 3 + it % 3)
            val q = FloatArray(4).also { SensorManager.getQuaternionFromVector(it, rv) }
            val aosp = dev.motionfusion.core.Quaternion(q[0].toDouble(), q[1].toDouble(), q[2].toDouble(), q[3].toDouble())
            if (aosp.norm() > 1e-3) {
                val typed = quaternionFromRotationVector(rv)
                assertEquals(1.0, typed.norm(), 1e-15)
                assertSameRotation(aosp.normalized(), typed, 1e-6)
                assertTrue(rotationMatrixFromRotationVector(rv).isRotationMatrix(1e-12))
            }
        }
        for (size in intArrayOf(0, 2, 6)) {
            val e = assertThrows<IllegalArgumentException> { quaternionFromRotationVector(FloatArray(size)) }
            assertTrue(e.message!!.contains("3 to 5"))
        }
    }

    @Test
    fun `altitudeM follows getAltitude and rejects non-physical pressures`() {
        repeat(n) {
            val p0 = 950.0 + rnd.nextDouble() * 100.0
            val p = 300.0 + rnd.nextDouble() * 800.0
            val expected = SensorManager.getAltitude(p0.toFloat(), p.toFloat()).toDouble()
            assertEquals(expected, altitudeM(p, p0), 1e-2 + 1e-5 * kotlin.math.abs(expected))
        }
        assertEquals(0.0, altitudeM(1013.25), 0.0)
        assertThrows(IllegalArgumentException::class.java) { altitudeM(0.0) }
        assertThrows(IllegalArgumentException::class.java) { altitudeM(1000.0, Double.NaN) }
    }
}
