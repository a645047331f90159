package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.math.atan2
import kotlin.math.hypot
import kotlin.random.Random

class AccelerationTest {

    private val rnd = Random(31)

    @Test
    fun `a device lying screen up at rest reads +g on z, and its linear acceleration is zero`() {
        assertClose(Vector3(0.0, 0.0, 9.80665), gravityInSensorFrame(Quaternion.IDENTITY), 0.0)
        assertClose(Vector3(0.0, 0.0, 1.62), gravityInSensorFrame(Quaternion.IDENTITY, g = 1.62), 0.0)
        // Standing upright in portrait (rotated +90° about x): gravity along the device's +y.
        val portrait = Quaternion.fromAxisAngle(Vector3.UNIT_X, PI / 2)
        assertClose(Vector3(0.0, 9.80665, 0.0), gravityInSensorFrame(portrait), 1e-14)
    }

    @Test
    fun `known motion is recovered in the sensor, earth and horizontal frames`() {
        repeat(10_000) {
            val q = Randoms.quaternion(rnd)
            val g = 9.7 + rnd.nextDouble() * 0.2
            val aWorld = Randoms.vector(rnd, 20.0) // true acceleration, ENU
            // What the accelerometer measures: specific force a − g⃗ = a + g·up, in the sensor frame.
            val f = q.inverseRotate(aWorld + Vector3(0.0, 0.0, g))
            assertClose(q.inverseRotate(aWorld), linearAccelerationInSensorFrame(f, q, g), 1e-12)
            val earth = linearAccelerationInEarthFrame(f, q, g)
            assertClose(aWorld, earth, 1e-12)
            val horizontal = linearAccelerationInHorizontalFrame(f, q, g)
            // Same vertical component and length as in the earth frame ...
            assertEquals(earth.z, horizontal.z, 1e-12)
            assertEquals(earth.norm(), horizontal.norm(), 1e-12)
            // ... and the device's y axis projected on the ground is the horizontal frame's +y.
            val yWorld = q.rotate(Vector3.UNIT_Y)
            if (hypot(yWorld.x, yWorld.y) > 1e-3) {
                val forward = Vector3(yWorld.x, yWorld.y, 0.0).normalized()
                val along = linearAccelerationInHorizontalFrame(q.inverseRotate(forward * 3.0 + Vector3(0.0, 0.0, g)), q, g)
                assertClose(Vector3(0.0, 3.0, 0.0), along, 1e-11)
                assertEquals(atan2(yWorld.x, yWorld.y), atan2(forward.x, forward.y), 1e-12)
            }
        }
    }

    @Test
    fun `at rest the linear acceleration is zero in every frame`() {
        repeat(10_000) {
            val q = Randoms.quaternion(rnd)
            val f = gravityInSensorFrame(q)
            assertEquals(9.80665, f.norm(), 1e-13)
            assertClose(Vector3.ZERO, linearAccelerationInSensorFrame(f, q), 1e-13)
            assertClose(Vector3.ZERO, linearAccelerationInEarthFrame(f, q), 1e-13)
            assertClose(Vector3.ZERO, linearAccelerationInHorizontalFrame(f, q), 1e-13)
        }
    }
}
