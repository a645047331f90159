package dev.motionfusion.core.sim

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.asin

class MotionSimulatorTest {
    private val noiseless = SimulationSettings(gyroNoise = 0.0, accNoise = 0.0, magNoise = 0.0, durationS = 10.0)

    @Test
    fun `equal seeds give equal streams, other seeds other streams`() {
        val s = SimulationSettings(durationS = 2.0, timestampJitter = 0.001, dropProbability = 0.1)
        assertEquals(MotionSimulator(s).run(), MotionSimulator(s).run())
        assertNotEquals(MotionSimulator(s).run(), MotionSimulator(s.copy(seed = 2L)).run())
    }

    @Test
    fun `integrating the noiseless gyroscope over the timestamps reproduces the truth`() {
        val data = MotionSimulator(noiseless.copy(timestampJitter = 0.001)).run()
        var q = data[0].truth
        for (i in 1 until data.size) {
            val dt = (data[i].timestampNs - data[i - 1].timestampNs) * 1e-9
            q = (q * Quaternion.fromRotationVector(data[i].gyro * dt)).normalized()
        }
        assertTrue(q.angleTo(data.last().truth) < 1e-6, "drift ${q.angleTo(data.last().truth)} rad")
    }

    @Test
    fun `accelerometer and magnetometer see gravity and the dipping field in the device frame`() {
        val data = MotionSimulator(noiseless).run()
        for (s in data) {
            assertTrue((s.truth.rotate(s.acc) - Vector3(0.0, 0.0, 9.80665)).norm() < 1e-9)
            val m = s.truth.rotate(s.mag)
            assertEquals(48.0, m.norm(), 1e-9)
            assertEquals(60.0, asin(-m.z / m.norm()) * 180.0 / PI, 1e-9)
            assertEquals(0.0, m.x, 1e-9) // magnetic north is ENU y
        }
    }

    @Test
    fun `bias, drift, hard iron, linear acceleration and rest windows appear where configured`() {
        val s = noiseless.copy(
            gyroBias = Vector3(0.01, 0.0, 0.0), gyroBiasDrift = 0.001, restWindows = listOf(TimeWindow(0.0, 2.0)),
            hardIron = Vector3(5.0, 0.0, 0.0), hardIronWindow = TimeWindow(3.0, 4.0),
            linearAcceleration = 2.0, linearAccelerationWindow = TimeWindow(5.0, 6.0),
        )
        val data = MotionSimulator(s).run()
        val atRest = data.filter { it.timestampNs < 1_900_000_000L }
        assertTrue(atRest.all { (it.gyro - Vector3(0.01, 0.0, 0.0)).norm() < 0.006 }, "rest reads the (drifting) bias only")
        assertTrue(atRest.all { it.truth == data[0].truth })
        val drifted = (data.last().gyro - MotionSimulator(s).angularVelocity(9.9975) - s.gyroBias).norm()
        assertTrue(drifted > 1e-5, "bias random walk")
        fun fieldError(it: SimulatedSample) = abs(it.truth.rotate(it.mag).norm() - 48.0)
        fun accError(it: SimulatedSample) = (it.truth.rotate(it.acc) - Vector3(0.0, 0.0, 9.80665)).norm()
        val inWindow = { a: Double, b: Double -> data.filter { it.timestampNs * 1e-9 in a..b } }
        assertTrue(inWindow(3.01, 3.99).all { fieldError(it) > 0.1 })
        assertTrue(inWindow(2.0, 2.99).all { fieldError(it) < 1e-9 })
        assertTrue(inWindow(5.01, 5.99).any { accError(it) > 1.0 })
        assertTrue(inWindow(6.01, 10.0).all { accError(it) < 1e-9 })
    }

    @Test
    fun `dropped samples leave gaps and jitter moves the instants`() {
        val data = MotionSimulator(noiseless.copy(durationS = 100.0, dropProbability = 0.1, timestampJitter = 0.0005)).run()
        val dropped = 20_000 - data.size
        assertTrue(dropped in 1_700..2_300, "dropped $dropped of 20000")
        val gaps = data.zipWithNext { a, b -> b.timestampNs - a.timestampNs }
        assertTrue(gaps.all { it > 0 })
        assertTrue(gaps.any { it > 9_000_000 })
        assertTrue(gaps.count { abs(it - 5_000_000) > 100_000 } > data.size / 2)
    }

    @Test
    fun `settings are validated`() {
        assertThrows(IllegalArgumentException::class.java) { SimulationSettings(rateHz = 0.0) }
        assertThrows(IllegalArgumentException::class.java) { SimulationSettings(gyroNoise = -1.0) }
        assertThrows(IllegalArgumentException::class.java) { SimulationSettings(timestampJitter = 0.01) }
        assertThrows(IllegalArgumentException::class.java) { TimeWindow(2.0, 1.0) }
    }
}
