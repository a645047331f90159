package dev.motionfusion.core.sim

import dev.motionfusion.core.Vector3
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import java.security.MessageDigest

/**
 * The simulator's output for settings without the sensor-error options must stay bit for bit
 * what it was before those options existed (samples and tests built on it stay reproducible).
 * The digests were taken with the simulator as it was before the sensor-error model was added.
 */
class SimulatorReproducibilityTest {
    private fun digest(settings: SimulationSettings): String {
        val md = MessageDigest.getInstance("SHA-256")
        val buf = java.nio.ByteBuffer.allocate(8 * 17)
        for (s in MotionSimulator(settings).run()) {
            buf.clear()
            buf.putLong(s.timestampNs)
            for (v in listOf(s.gyro, s.acc, s.mag)) { buf.putDouble(v.x); buf.putDouble(v.y); buf.putDouble(v.z) }
            buf.putDouble(s.truth.w); buf.putDouble(s.truth.x); buf.putDouble(s.truth.y); buf.putDouble(s.truth.z)
            md.update(buf.array(), 0, buf.position())
        }
        return md.digest().joinToString("") { "%02x".format(it) }
    }

    @Test
    fun `default settings give the same stream as before`() {
        assertEquals("8981676528eee00dc68bbc31bc9915faf6a8fc8a50a9affc5128ef424696b7b3", digest(SimulationSettings(durationS = 5.0)))
    }

    @Test
    fun `the CLI's simulate settings give the same stream as before`() {
        val s = SimulationSettings(
            seed = 8L, rateHz = 100.0, durationS = 20.0,
            restWindows = listOf(TimeWindow(0.0, 2.0), TimeWindow(18.0, 21.0)),
            gyroBias = Vector3(0.01, -0.02, 0.015), timestampJitter = 0.0002,
            gyroBiasDrift = 0.001, hardIron = Vector3(5.0, -3.0, 2.0), hardIronWindow = TimeWindow(5.0, 8.0),
            dropProbability = 0.05, linearAcceleration = 1.0, linearAccelerationWindow = TimeWindow(3.0, 9.0),
        )
        assertEquals("2e184f27d1d27511ddc3d5b43edffbee99d1efd232433ce5b7d1917cd2cc989b", digest(s))
    }
}
