package dev.motionfusion.core.replay

import dev.motionfusion.core.AerospaceAngles
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.convertOrientation
import dev.motionfusion.core.eval.BroadMetric
import dev.motionfusion.core.linearAccelerationInEarthFrame
import dev.motionfusion.core.sensormanager.androidOrientation
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.util.Random
import kotlin.math.abs

class ReplayOutputTest {
    private val random = Random(11)

    private fun randomQuaternion(): Quaternion =
        Quaternion(random.nextGaussian(), random.nextGaussian(), random.nextGaussian(), random.nextGaussian()).normalized()

    private fun angleDiff(a: Double, b: Double): Double = abs(Math.IEEEremainder(a - b, 360.0))

    /** Body "phone as aircraft": x forward = device y, y right = device x, z down = −device z. */
    private val bodyToDevice = Quaternion(0.0, Math.sqrt(0.5), Math.sqrt(0.5), 0.0)

    @Test
    fun `derived angles and linear acceleration agree with the core math`() {
        val out = DoubleArray(9)
        repeat(20_000) { i ->
            var q = randomQuaternion()
            if (i % 100 == 0) {
                // Gimbal lock: the phone's top edge straight up or down.
                q = Quaternion.fromAxisAngle(Vector3.UNIT_X, if (i % 200 == 0) Math.PI / 2 else -Math.PI / 2) *
                    Quaternion.fromAxisAngle(Vector3.UNIT_Y, random.nextDouble() * 6.0)
                q = Quaternion.fromAxisAngle(Vector3.UNIT_Z, random.nextDouble() * 6.0) * q
            }
            val a = doubleArrayOf(random.nextGaussian() * 5, random.nextGaussian() * 5, random.nextGaussian() * 5 + 9.8)
            ReplayCsvWriter.derived(q.toDoubleArray(), a, out)
            if (i % 100 != 0) {
                val android = androidOrientation(q.toRotationMatrix())
                assertEquals(android.azimuthDeg, out[0], 1e-9)
                assertEquals(android.pitchDeg, out[1], 1e-9)
                assertEquals(android.rollDeg, out[2], 1e-9)
            }
            // Aerospace: body → NED = c ⊗ q ⊗ p with c: ENU → NED and p: body → device.
            val bodyToNed = convertOrientation(q, WorldFrame.ENU, WorldFrame.NED) * bodyToDevice
            val aero = AerospaceAngles.fromQuaternion(bodyToNed)
            val tol = if (i % 100 == 0) 1e-4 else 1e-6
            assertEquals(0.0, angleDiff(Math.toDegrees(aero.yaw), out[3]), tol, "yaw $i")
            assertEquals(Math.toDegrees(aero.pitch), out[4], tol, "pitch $i")
            assertEquals(0.0, angleDiff(Math.toDegrees(aero.roll), out[5]), tol, "roll $i")
            val lin = linearAccelerationInEarthFrame(Vector3(a[0], a[1], a[2]), q)
            assertEquals(lin.x, out[6], 1e-9)
            assertEquals(lin.y, out[7], 1e-9)
            assertEquals(lin.z, out[8], 1e-9)
        }
    }

    @Test
    fun `an unknown orientation gives NaN in every derived column`() {
        val out = DoubleArray(9)
        ReplayCsvWriter.derived(DoubleArray(4) { Double.NaN }, doubleArrayOf(0.0, 0.0, 9.8), out)
        for (k in 0 until 9) assertEquals(true, out[k].isNaN(), "column $k: ${out[k]}")
    }

    @Test
    fun `comparison errors agree with BROAD's metric, and interpolation removes rate differences`() {
        // Estimates at 200 Hz of a rotation about z at 1 rad/s; reference at 50 Hz, offset 1 ms, with a 3° tilt error.
        val tilt = Quaternion.fromAxisAngle(Vector3.UNIT_X, Math.toRadians(3.0))
        val est = ArrayList<DoubleArray>()
        val ref = ArrayList<DoubleArray>()
        val c = OrientationComparison { _, _, _, _ -> }
        for (k in 0 until 2000) {
            val t = k * 5_000_000L
            if (k % 4 == 1) {
                val tr = t - 1_000_000L
                val truth = Quaternion.fromAxisAngle(Vector3.UNIT_Z, tr * 1e-9)
                val r = tilt * truth
                c.reference(tr, r.w, r.x, r.y, r.z)
                est += Quaternion.fromAxisAngle(Vector3.UNIT_Z, tr * 1e-9).toDoubleArray()
                ref += r.toDoubleArray()
            }
            c.estimate(t, Quaternion.fromAxisAngle(Vector3.UNIT_Z, t * 1e-9).toDoubleArray())
        }
        val broad = BroadMetric.rmse(est.toTypedArray(), ref.toTypedArray(), BooleanArray(est.size) { true }, removeHeadingOffset = false)
        assertEquals(500L, c.total.count)
        assertEquals(3.0, c.total.rms, 1e-6)
        assertEquals(broad.totalDeg, c.total.rms, 1e-6)
        assertEquals(broad.headingDeg, c.heading.rms, 1e-6)
        assertEquals(broad.inclinationDeg, c.inclination.rms, 1e-6)
        assertEquals(3.0, c.total.percentile(0.5), 0.01)
        assertEquals(3.0, c.total.max, 1e-6)
    }
}
