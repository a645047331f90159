package dev.motionfusion.core.filter

import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import dev.motionfusion.core.sim.TimeWindow
import org.junit.jupiter.api.Assertions.assertArrayEquals
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNotEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import kotlin.math.PI
import kotlin.math.cos
import kotlin.math.sin

/** Frames, input validation, state/restore and settings. */
class FilterApiTest {
    private val g = 9.80665
    private val dip = 60.0 * PI / 180.0

    /** Device lying flat, screen up, top edge (y) pointing to magnetic north. */
    private fun flatNorth(settings: FilterSettings): MadgwickFilter = MadgwickFilter(settings).apply {
        update(0L, 0.0, 0.0, 0.0, 0.0, 0.0, g, 0.0, 40.0 * cos(dip), -40.0 * sin(dip))
    }

    private fun assertVector(expected: Vector3, actual: Vector3) =
        assertTrue((expected - actual).norm() < 1e-9, "expected $expected, got $actual")

    @Test
    fun `outputs ENU by default, NWU and NED on request`() {
        val enu = flatNorth(FilterSettings()).orientation()
        assertTrue(enu.angleTo(Quaternion.IDENTITY) < 1e-9, "ENU: $enu")
        // Device y points north, device x east, device z up, in each frame's own coordinates.
        val nwu = flatNorth(FilterSettings(outputFrame = WorldFrame.NWU)).orientation()
        assertVector(Vector3(1.0, 0.0, 0.0), nwu.rotate(Vector3.UNIT_Y))
        assertVector(Vector3(0.0, -1.0, 0.0), nwu.rotate(Vector3.UNIT_X))
        val ned = flatNorth(FilterSettings(outputFrame = WorldFrame.NED)).orientation()
        assertVector(Vector3(1.0, 0.0, 0.0), ned.rotate(Vector3.UNIT_Y))
        assertVector(Vector3(0.0, 1.0, 0.0), ned.rotate(Vector3.UNIT_X))
        assertVector(Vector3(0.0, 0.0, -1.0), ned.rotate(Vector3.UNIT_Z))
    }

    @Test
    fun `a stream's reading goes to that sensor's update, other streams to none`() {
        val data = MotionSimulator(SimulationSettings(durationS = 5.0, hardIron = Vector3(40.0, 0.0, 0.0), hardIronWindow = TimeWindow(2.0, 3.0))).run()
        val settings = FilterSettings(magDisturbanceRejection = true)
        val direct = MadgwickFilter(settings)
        val dispatched = MadgwickFilter(settings)
        var steps = 0
        for (s in data) {
            val t = s.timestampNs
            direct.updateAccelerometer(t, s.acc.x, s.acc.y, s.acc.z)
            direct.updateMagnetometer(t, s.mag.x, s.mag.y, s.mag.z)
            direct.updateGyroscope(t, s.gyro.x, s.gyro.y, s.gyro.z)
            assertFalse(dispatched.update(SessionStream.ACCELEROMETER, t, s.acc.x, s.acc.y, s.acc.z))
            assertFalse(dispatched.update(SessionStream.MAGNETOMETER, t, s.mag.x, s.mag.y, s.mag.z))
            // Not filter inputs: the phone's own orientation and the raw streams change nothing.
            assertFalse(dispatched.update(SessionStream.ROTATION_VECTOR, t, 0.5, 0.5, 0.5))
            assertFalse(dispatched.update(SessionStream.GYROSCOPE_UNCALIBRATED, t, 9.0, 9.0, 9.0))
            if (dispatched.update(SessionStream.GYROSCOPE, t, s.gyro.x, s.gyro.y, s.gyro.z)) steps++
        }
        assertEquals(data.size, steps)
        assertEquals(direct.state(), dispatched.state())
        assertEquals(direct.diagnostics(), dispatched.diagnostics())
    }

    @Test
    fun `orientationInto writes the same quaternion at an offset`() {
        val f = flatNorth(FilterSettings())
        val out = DoubleArray(6) { -7.0 }
        f.orientationInto(out, 2)
        assertArrayEquals(doubleArrayOf(-7.0, -7.0) + f.orientation().toDoubleArray(), out)
    }

    @Test
    fun `waits for an accelerometer sample before starting`() {
        val f = MadgwickFilter()
        f.updateGyroscope(1_000L, 0.1, 0.0, 0.0)
        assertFalse(f.isInitialised)
        assertEquals(Quaternion.IDENTITY, f.orientation())
        assertEquals(1L, f.diagnostics().skippedBeforeInit)
    }

    @Test
    fun `in MARG mode waits up to maxGap for a magnetometer sample, then starts without heading`() {
        val f = MadgwickFilter()
        f.updateAccelerometer(0L, 0.0, 0.0, g)
        f.updateGyroscope(0L, 0.0, 0.0, 0.0)
        assertFalse(f.isInitialised)
        f.updateAccelerometer(600_000_000L, 0.0, 0.0, g)
        f.updateGyroscope(600_000_000L, 0.0, 0.0, 0.0)
        assertTrue(f.isInitialised)
    }

    @Test
    fun `bad samples are counted and never reach the state`() {
        val f = flatNorth(FilterSettings())
        val t = 10_000_000L
        f.update(t, Double.NaN, 0.0, 0.0, 0.0, 0.0, g, 20.0, 0.0, -30.0)
        f.update(t + 1, 0.0, 0.0, 0.0, Double.POSITIVE_INFINITY, 0.0, g, 20.0, 0.0, -30.0)
        f.update(t + 2, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 20.0, 0.0, -30.0)
        f.update(t + 3, 0.0, 0.0, 0.0, 0.0, 0.0, g, 0.0, 0.0, 0.0)
        f.update(t + 3, 0.0, 0.0, 0.0, 0.0, 0.0, g, 20.0, 0.0, -30.0) // same timestamp
        f.update(t - 5, 0.0, 0.0, 0.0, 0.0, 0.0, g, 20.0, 0.0, -30.0) // backwards
        f.update(t + 2_000_000_000L, 0.0, 0.0, 0.0, 0.0, 0.0, g, 20.0, 0.0, -30.0) // 2 s gap
        f.update(t + 2_010_000_000L, 1e300, 1e300, 1e300, 0.0, 0.0, g, 20.0, 0.0, -30.0) // finite but beyond any phone's range
        val d = f.diagnostics()
        assertEquals(2L, d.skippedNonFinite, "NaN gyro, infinite acc: $d")
        assertEquals(1L, d.skippedOutOfRange, "the absurd gyroscope reading: $d")
        assertEquals(2L, d.skippedZero, "zero acc, zero mag: $d")
        assertEquals(2L, d.skippedTimestamp, "duplicate and backward timestamps: $d")
        assertEquals(1L, d.skippedGap)
        assertTrue(f.orientation().isFinite())
        assertTrue(d.gyroBias.isFinite())
    }

    @Test
    fun `stale accelerometer and magnetometer samples are not used`() {
        val f = flatNorth(FilterSettings())
        for (k in 1..6) f.updateGyroscope(k * 100_000_000L, 0.0, 0.0, 0.0)
        assertEquals(1L, f.diagnostics().staleSamples, "only the step at 600 ms has samples older than 500 ms")
    }

    @Test
    fun `a run split in two and restored equals the unsplit run`() {
        val data = MotionSimulator(
            SimulationSettings(
                durationS = 40.0, gyroBias = Vector3(0.02, 0.0, -0.01), restWindows = listOf(TimeWindow(0.0, 5.0), TimeWindow(25.0, 28.0)),
                hardIron = Vector3(40.0, 0.0, 0.0), hardIronWindow = TimeWindow(10.0, 15.0), linearAcceleration = 5.0,
                linearAccelerationWindow = TimeWindow(17.0, 20.0),
            ),
        ).run()
        val settings = FilterSettings(accRejection = true, zeta = 0.001)
        val whole = MadgwickFilter(settings)
        data.forEach { whole.update(it.timestampNs, it.gyro, it.acc, it.mag) }
        for (split in listOf(1, data.size / 3, 2 * data.size / 3)) {
            val first = MadgwickFilter(settings)
            data.take(split).forEach { first.update(it.timestampNs, it.gyro, it.acc, it.mag) }
            val second = MadgwickFilter(settings)
            second.restore(first.state())
            assertEquals(first.state(), second.state())
            data.drop(split).forEach { second.update(it.timestampNs, it.gyro, it.acc, it.mag) }
            assertEquals(whole.orientation(), second.orientation(), "split at $split")
            assertEquals(whole.diagnostics(), second.diagnostics(), "split at $split")
            assertEquals(whole.state(), second.state(), "split at $split")
        }
        assertNotEquals(MadgwickFilter(settings).state(), whole.state())
        assertThrows(IllegalArgumentException::class.java) { MadgwickFilter(FilterSettings()).restore(whole.state()) }
    }

    @Test
    fun `IMU mode ignores the magnetometer`() {
        val f = MadgwickFilter(FilterSettings(mode = FilterMode.IMU))
        f.update(0L, 0.0, 0.0, 0.0, 0.0, 0.0, g, 40.0, 0.0, -30.0)
        val q = f.orientation()
        f.update(5_000_000L, 0.0, 0.0, 0.0, 0.0, 0.0, g, -40.0, 10.0, 30.0)
        assertEquals(q, f.orientation())
    }

    @Test
    fun `settings are validated`() {
        assertThrows(IllegalArgumentException::class.java) { FilterSettings(beta = -0.1) }
        assertThrows(IllegalArgumentException::class.java) { FilterSettings(zeta = Double.NaN) }
        assertThrows(IllegalArgumentException::class.java) { FilterSettings(maxGap = 0.0) }
        assertThrows(IllegalArgumentException::class.java) { FilterSettings(magDipTolerance = 2.0) }
        assertThrows(IllegalArgumentException::class.java) { FilterSettings(restBiasTime = Double.POSITIVE_INFINITY) }
        assertEquals(Initialisation.IDENTITY, FilterSettings.report().initialisation)
    }
}
