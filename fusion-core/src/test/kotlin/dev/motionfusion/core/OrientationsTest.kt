package dev.motionfusion.core

import android.hardware.SensorManager
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.acos
import kotlin.math.cos
import kotlin.random.Random

/** The one home of the orientation conversions, against references it does not share code with. */
class OrientationsTest {
    private val rnd = Random(77)
    private val n = 20_000

    private fun angleDiff(a: Double, b: Double): Double = abs(Math.IEEEremainder(a - b, 2 * PI))

    @Test
    fun `Android angles equal the real SensorManager's getOrientation of getRotationMatrixFromVector`() {
        val r = FloatArray(9)
        val expected = FloatArray(3)
        val out = DoubleArray(6)
        var compared = 0
        repeat(n) {
            val q = Randoms.quaternion(rnd)
            // The rotation vector as Android gives it: x, y, z, w (device → ENU).
            SensorManager.getRotationMatrixFromVector(r, floatArrayOf(q.x.toFloat(), q.y.toFloat(), q.z.toFloat(), q.w.toFloat()))
            SensorManager.getOrientation(r, expected)
            Orientations.androidAndAerospaceAngles(q.toDoubleArray(), out, 0)
            val typed = Orientations.androidAngles(q)
            assertEquals(out[0], typed.azimuth, 0.0)
            assertEquals(out[1], typed.pitch, 0.0)
            assertEquals(out[2], typed.roll, 0.0)
            // Float asin is ill-conditioned near ±90°: compare sin(pitch), i.e. −R21.
            assertEquals(kotlin.math.sin(expected[1].toDouble()), kotlin.math.sin(out[1]), 1e-6, "pitch")
            if (cos(out[1]) > 0.01) { // azimuth and roll are ill-conditioned at the pole
                compared++
                assertEquals(0.0, angleDiff(expected[0].toDouble(), out[0]), 1e-4, "azimuth")
                assertEquals(0.0, angleDiff(expected[2].toDouble(), out[2]), 1e-4, "roll")
                assertEquals(out[0], Orientations.azimuth(q.toDoubleArray()), 1e-15)
            }
            val m = Orientations.androidAngles(q.toRotationMatrix())
            assertEquals(0.0, angleDiff(m.azimuth, out[0]), 1e-9)
            assertEquals(m.pitch, out[1], 1e-9)
        }
        assertTrue(compared > n * 9 / 10, "compared $compared")
    }

    @Test
    fun `phone aerospace angles equal the general Z-Y-X decomposition of body to NED`() {
        // Body "phone as aircraft": x forward = device y, y right = device x, z down = −device z.
        val bodyToDevice = Quaternion(0.0, Math.sqrt(0.5), Math.sqrt(0.5), 0.0)
        repeat(n) {
            val q = Randoms.quaternion(rnd)
            val aero = Orientations.phoneAerospaceAngles(q)
            val reference = AerospaceAngles.fromQuaternion(convertOrientation(q, WorldFrame.ENU, WorldFrame.NED) * bodyToDevice)
            assertEquals(0.0, angleDiff(reference.yaw, aero.yaw), 1e-7)
            assertEquals(reference.pitch, aero.pitch, 1e-7)
            assertEquals(0.0, angleDiff(reference.roll, aero.roll), 1e-7)
        }
        val nan = DoubleArray(6)
        Orientations.androidAndAerospaceAngles(DoubleArray(4) { Double.NaN }, nan, 0)
        assertTrue(nan.all { it.isNaN() })
    }

    @Test
    fun `slerp follows the exponential map along the shorter arc`() {
        val out = DoubleArray(4)
        repeat(n) {
            val a = Randoms.quaternion(rnd)
            var b = Randoms.quaternion(rnd)
            if (it % 10 == 0) b = (a * Quaternion.fromRotationVector(Randoms.vector(rnd, 1e-3))).let { c -> if (it % 20 == 0) -c else c }
            val t = rnd.nextDouble()
            // a ⊗ exp(t · log(a* ⊗ b)), log taken on the canonical (shorter-arc) form.
            val expected = a * Quaternion.fromRotationVector((a.conjugate() * b).toRotationVector() * t)
            Orientations.slerp(a.toDoubleArray(), b.toDoubleArray(), t, out)
            assertSameRotation(expected, Quaternion(out[0], out[1], out[2], out[3]), 1e-9) { "t $t" }
            assertSameRotation(expected, a.slerp(b, t), 1e-9)
        }
    }

    @Test
    fun `the error splits into the angle between the orientations, a heading and the angle between the up directions`() {
        val split = DoubleArray(3)
        val e = DoubleArray(4)
        repeat(n) {
            val q = Randoms.quaternion(rnd)
            val r = Randoms.quaternion(rnd)
            val err = Orientations.error(q, r)
            assertEquals(q.angleTo(r), err.total, 1e-9)
            // Inclination: the tilt difference, the angle between the up directions seen from the sensor.
            val uq = q.inverseRotate(Vector3.UNIT_Z)
            val ur = r.inverseRotate(Vector3.UNIT_Z)
            assertEquals(acos((uq dot ur).coerceIn(-1.0, 1.0)), err.inclination, 1e-6)
            assertTrue(err.heading in 0.0..PI && err.total >= err.inclination - 1e-12)
            // A pure heading error of ψ on top of r: heading |ψ|, no inclination; removing it leaves nothing.
            val psi = (rnd.nextDouble() * 2 - 1) * 3.1
            val turned = Quaternion.fromAxisAngle(Vector3.UNIT_Z, psi) * r
            Orientations.errorQuaternion(turned.toDoubleArray(), r.toDoubleArray(), e)
            assertEquals(psi, Orientations.signedHeading(e), 1e-9)
            Orientations.splitError(e, split, 0)
            assertEquals(abs(psi), split[1], 1e-9)
            assertEquals(0.0, split[2], 1e-6)
            Orientations.removeHeading(e, psi)
            Orientations.splitError(e, split, 0)
            assertEquals(0.0, split[0], 1e-6)
            // A pure tilt error θ about a horizontal axis: no heading.
            val theta = rnd.nextDouble() * 3.0
            val tilted = Quaternion.fromAxisAngle(Vector3(cos(psi), kotlin.math.sin(psi), 0.0), theta) * r
            val t = Orientations.error(tilted, r)
            assertEquals(theta, t.inclination, 1e-6)
            assertEquals(0.0, t.heading, 1e-9)
        }
    }
}
