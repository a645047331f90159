package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.EllipsoidModel
import dev.motionfusion.core.calib.GyroscopeCalibration
import dev.motionfusion.core.calib.MagnetometerCalibration
import dev.motionfusion.core.calib.Matrix3
import dev.motionfusion.core.calib.SensorCorrection
import dev.motionfusion.core.event.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.lang.management.ManagementFactory

/** The capture with a calibration applied: which stream feeds the filter, with what values, at what cost. */
class CalibratedCaptureTest {
    private val softIron = Matrix3.symmetric(1.1, 0.9, 1.0, 0.05, 0.0, -0.03)
    private val calibration = Calibration(
        magnetometer = MagnetometerCalibration(
            SensorCorrection(Vector3(35.0, -20.0, 60.0), softIron), SessionStream.MAGNETOMETER_UNCALIBRATED, EllipsoidModel.FULL, 50.0, 0.3, 0.8, 5000, 10.0, 0.3,
        ),
        gyroscope = GyroscopeCalibration(Vector3(0.02, -0.01, 0.015), SessionStream.GYROSCOPE_UNCALIBRATED, 30.0, 10, Vector3(1e-5, 1e-5, 1e-5), Vector3(0.003, 0.003, 0.003)),
    )

    private val acc = floatArrayOf(0.1f, 0.2f, 9.8f)
    private val magRaw = floatArrayOf(55f, -10f, 20f, 30f, -15f, 50f)
    private val mag = floatArrayOf(25f, 5f, -30f)
    private val gyroRaw = floatArrayOf(0.03f, -0.01f, 0.015f, 0.01f, 0f, 0f)
    private val gyro = floatArrayOf(0.02f, -0.01f, 0.015f)

    /** [n] rounds of five streams into the ring as the sensor thread offers them (no allocation here). */
    private fun deliver(c: TestCapture, from: Long, n: Int) {
        for (i in 0 until n) {
            val t = from + i * 10_000_000L
            c.ring.offer(SessionStream.ACCELEROMETER, t, 3, acc, 3)
            c.ring.offer(SessionStream.MAGNETOMETER_UNCALIBRATED, t + 100_000, 3, magRaw, 6)
            c.ring.offer(SessionStream.MAGNETOMETER, t + 150_000, 3, mag, 3)
            c.ring.offer(SessionStream.GYROSCOPE_UNCALIBRATED, t + 200_000, 3, gyroRaw, 6)
            c.ring.offer(SessionStream.GYROSCOPE, t + 250_000, 3, gyro, 3)
            if (i % 16 == 15) c.capture.pump()
        }
        c.drain()
        c.nowNs += 1_000_000_000L
        c.capture.pump()
    }

    @Test
    fun `the corrected uncalibrated streams feed the filter in place of Android's, without allocating per event`() {
        val c = TestCapture(publishIntervalNs = Long.MAX_VALUE / 4, calibration = calibration)
        deliver(c, 1_000_000_000L, 200) // warm up
        assertEquals(calibration, c.capture.calibrationInUse())
        val me = Thread.currentThread().id
        val threads = ManagementFactory.getThreadMXBean() as com.sun.management.ThreadMXBean
        val before = threads.getThreadAllocatedBytes(me)
        deliver(c, 10_000_000_000L, 4000)
        val perEvent = (threads.getThreadAllocatedBytes(me) - before) / 20_000.0
        println("capture with a calibration applied: %.3f bytes per event".format(perEvent))
        assertTrue(perEvent < 1.0, "$perEvent bytes per event")

        val state = TestCapture(calibration = calibration).also { deliver(it, 1_000_000_000L, 10) }.capture.state.value
        val mag = state.sensors.getValue(SensorKind.MAGNETOMETER)
        // W · (raw − offset) of the uncalibrated reading, not Android's (25, 5, −30).
        val expected = softIron * (Vector3(55.0, -10.0, 20.0) - Vector3(35.0, -20.0, 60.0))
        assertEquals(expected.x, mag.x.toDouble(), 1e-4)
        assertEquals(expected.y, mag.y.toDouble(), 1e-4)
        assertEquals(expected.z, mag.z.toDouble(), 1e-4)
        assertEquals(expected.norm(), state.magneticFieldUt!!, 1e-4)
        val gyro = state.sensors.getValue(SensorKind.GYROSCOPE)
        assertEquals(10L, gyro.samples, "one gyroscope stream reaches the filter: the corrected uncalibrated one")
        assertEquals(0.01, gyro.x.toDouble(), 1e-6)

        // Without a calibration, Android's streams.
        val plain = TestCapture().also { deliver(it, 1_000_000_000L, 10) }
        assertNull(plain.capture.calibrationInUse())
        assertEquals(25f, plain.capture.state.value.sensors.getValue(SensorKind.MAGNETOMETER).x)
        assertEquals(0.02f, plain.capture.state.value.sensors.getValue(SensorKind.GYROSCOPE).x)
    }
}
