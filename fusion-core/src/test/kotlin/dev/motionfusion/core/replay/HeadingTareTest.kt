package dev.motionfusion.core.replay

import dev.motionfusion.core.Orientations
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.util.Random
import kotlin.math.abs

/** The heading tare turns the output frame about up only: heading + Δ, pitch, roll and every vector's vertical component as before. */
class HeadingTareTest {
    private val random = Random(5)

    private fun randomQuaternion(): Quaternion =
        Quaternion(random.nextGaussian(), random.nextGaussian(), random.nextGaussian(), random.nextGaussian()).normalized()

    private fun wrapDiff(a: Double, b: Double) = abs(Math.IEEEremainder(a - b, 2 * Math.PI))

    /** Steps through [tare] with orientation [q]; returns the tared quaternion. */
    private class Capture : ReplayListener {
        val q = DoubleArray(4)
        override fun step(step: ReplayStep) { step.orientation.copyInto(q) }
    }

    private fun step(q: Quaternion, timeS: Double = 0.0) = ReplayStep().also {
        it.initialised = true
        it.timeS = timeS
        q.toDoubleArray().copyInto(it.orientation)
    }

    @Test
    fun `an offset adds to every heading and leaves pitch, roll and the vertical unchanged`() {
        val before = DoubleArray(6)
        val after = DoubleArray(6)
        repeat(5000) {
            val q = randomQuaternion()
            val delta = (random.nextDouble() * 2 - 1) * 4.0
            val c = Capture()
            HeadingTare.offset(c, delta).step(step(q))
            val t = Quaternion(c.q[0], c.q[1], c.q[2], c.q[3])
            assertEquals(1.0, t.norm(), 1e-12)
            Orientations.androidAndAerospaceAngles(q.toDoubleArray(), before, 0)
            Orientations.androidAndAerospaceAngles(c.q, after, 0)
            assertEquals(0.0, wrapDiff(before[3] + delta, after[3]), 1e-9, "heading + Δ")
            assertEquals(before[4], after[4], 1e-9, "pitch")
            if (abs(before[4]) < 1.5) assertEquals(0.0, wrapDiff(before[5], after[5]), 1e-9, "roll")
            // Each device axis keeps its up component, and its horizontal part turns by −Δ about up.
            for (v in listOf(Vector3.UNIT_X, Vector3.UNIT_Y, Vector3.UNIT_Z)) {
                val a = q.rotate(v)
                val b = t.rotate(v)
                assertEquals(a.z, b.z, 1e-12)
                assertEquals(a.x * Math.cos(-delta) - a.y * Math.sin(-delta), b.x, 1e-12)
                assertEquals(a.x * Math.sin(-delta) + a.y * Math.cos(-delta), b.y, 1e-12)
            }
        }
    }

    @Test
    fun `a tare at the start sets the first orientation's heading and keeps the offset after it`() {
        val c = Capture()
        val tare = HeadingTare.atStart(c, Math.toRadians(30.0))
        val uninitialised = ReplayStep().also { it.orientation.fill(Double.NaN) }
        tare.step(uninitialised)
        assertEquals(true, tare.offsetRad.isNaN())
        val q0 = randomQuaternion()
        tare.step(step(q0))
        assertEquals(Math.toRadians(30.0), HeadingTare.heading(c.q), 1e-12)
        val offset = tare.offsetRad
        assertEquals(0.0, wrapDiff(HeadingTare.heading(q0.toDoubleArray()) + offset, Math.toRadians(30.0)), 1e-12)
        val q1 = randomQuaternion()
        tare.step(step(q1, 1.0))
        assertEquals(offset, tare.offsetRad)
        assertEquals(0.0, wrapDiff(HeadingTare.heading(q1.toDoubleArray()) + offset, HeadingTare.heading(c.q)), 1e-9)
    }

    @Test
    fun `the probe takes the first orientation at or after its time`() {
        val p = HeadingProbe(1.0)
        val a = randomQuaternion()
        val b = randomQuaternion()
        p.step(step(a, 0.5))
        p.step(step(b, 1.0))
        p.step(step(a, 1.5))
        assertEquals(HeadingTare.heading(b.toDoubleArray()), p.headingRad)
        assertEquals(1.0, p.timeS)
    }
}
