package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSample
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNotNull
import org.junit.jupiter.api.Assertions.assertNotSame
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertSame
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import dev.motionfusion.app.settings.AngleConvention
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.fusion.EffectiveMode
import dev.motionfusion.app.fusion.FusionMode
import dev.motionfusion.app.fusion.FusionPipeline
import dev.motionfusion.app.fusion.ModeReason
import dev.motionfusion.app.fusion.effectiveMode

/** The fusion pipeline without Android: pairing, fallbacks, references, statistics. */
class FusionPipelineTest {
    private val all = SensorKind.entries.toSet()
    private val ms = 1_000_000L

    private fun acc(t: Long, x: Float, y: Float, z: Float) = SensorSample(SensorKind.ACCELEROMETER, t, x, y, z, 3)
    private fun mag(t: Long, x: Float, y: Float, z: Float, accuracy: Int = 3) = SensorSample(SensorKind.MAGNETOMETER, t, x, y, z, accuracy)
    private fun gyro(t: Long, x: Float = 0f, y: Float = 0f, z: Float = 0f) = SensorSample(SensorKind.GYROSCOPE, t, x, y, z, 3)

    private fun angles(p: FusionPipeline, convention: AngleConvention = AngleConvention.ANDROID): DisplayAngles {
        val q = p.snapshot().orientation
        assertNotNull(q, "an orientation")
        return Readout.angles(q!!, 0, convention)
    }

    /** Difference folded into (−180, 180]. */
    private fun wrapped(d: Double): Double = ((d % 360.0) + 540.0) % 360.0 - 180.0

    @Test
    fun `the filter waits for a gyroscope sample and steps on each one with the held samples`() {
        val p = FusionPipeline(all, LiveSettings())
        p.onSample(acc(0, 0f, 0f, 9.81f))
        p.onSample(mag(1 * ms, 0f, 22f, -40f))
        assertNull(p.snapshot().orientation, "accelerometer and magnetometer alone do not step the filter")
        p.onSample(gyro(2 * ms))
        val first = p.snapshot()
        assertNotNull(first.orientation)
        assertEquals(0L, first.filterSteps, "the first gyroscope sample initialises")
        for (i in 1..9) p.onSample(gyro(2 * ms + i * 10 * ms))
        assertEquals(9L, p.snapshot().filterSteps)
        val a = angles(p)
        // Within 0.05°: Madgwick's normalised gradient turns the rounding-level residual at the
        // solution into full steps of up to 2βΔt (0.023° here), so the estimate chatters around it.
        assertEquals(0.0, wrapped(a.yaw), 0.05); assertEquals(0.0, a.pitch, 0.05); assertEquals(0.0, a.roll, 0.05)
    }

    @Test
    fun `top towards east starts at azimuth 90`() {
        val p = FusionPipeline(all, LiveSettings())
        p.onSample(acc(0, 0f, 0f, 9.81f))
        p.onSample(mag(0, -22f, 0f, -40f))
        p.onSample(gyro(ms))
        assertEquals(90.0, angles(p).yaw, 1e-4)
    }

    @Test
    fun `gyroscope turns are integrated between samples (6D)`() {
        val p = FusionPipeline(all, LiveSettings(filter = FilterSettings(mode = FilterMode.IMU, restBiasEstimation = false)))
        assertEquals(FusionMode.IMU, p.mode.mode)
        p.onSample(acc(0, 0f, 0f, 9.81f))
        p.onSample(gyro(0))
        val start = angles(p).yaw
        // 0.5 rad/s counter-clockwise (seen from above) about up for 1 s at 100 Hz: azimuth −28.65°.
        for (i in 1..100) {
            p.onSample(acc(i * 10 * ms, 0f, 0f, 9.81f))
            p.onSample(gyro(i * 10 * ms, z = 0.5f))
        }
        assertEquals(0.0, start, 1e-9, "6D: the relative heading starts at 0")
        assertEquals(-Math.toDegrees(0.5), wrapped(angles(p).yaw - start), 0.05)
        assertEquals(100L, p.snapshot().filterSteps)
    }

    @Test
    fun `without gyroscope the orientation comes from accelerometer and magnetometer`() {
        val p = FusionPipeline(setOf(SensorKind.ACCELEROMETER, SensorKind.MAGNETOMETER), LiveSettings())
        assertEquals(EffectiveMode(FusionMode.ACC_MAG, ModeReason.NO_GYROSCOPE), p.mode)
        p.onSample(acc(0, 0f, 0f, 9.81f))
        assertNull(p.snapshot().orientation)
        p.onSample(mag(ms, -22f, 0f, -40f))
        assertEquals(90.0, angles(p).yaw, 1e-3)
        // Free fall keeps the last orientation.
        p.onSample(acc(2 * ms, 0f, 0f, 0.1f))
        assertEquals(90.0, angles(p).yaw, 1e-3)
    }

    @Test
    fun `with the accelerometer alone there is tilt, also upside down`() {
        val p = FusionPipeline(setOf(SensorKind.ACCELEROMETER), LiveSettings())
        assertEquals(FusionMode.TILT_ONLY, p.mode.mode)
        val s = Math.sin(Math.toRadians(30.0)).toFloat() * 9.81f
        val c = Math.cos(Math.toRadians(30.0)).toFloat() * 9.81f
        p.onSample(acc(0, 0f, s, c))
        assertEquals(-30.0, angles(p).pitch, 1e-4)
        assertEquals(0.0, angles(p).roll, 1e-4)
        p.onSample(acc(ms, 0f, 0f, -9.81f))
        assertEquals(180.0, Math.abs(angles(p).roll), 1e-4)
        assertEquals(0.0, angles(p).pitch, 1e-4)
    }

    @Test
    fun `rotation vectors are kept normalised, per kind`() {
        val p = FusionPipeline(all, LiveSettings())
        val h = Math.sqrt(0.5).toFloat()
        p.onSample(SensorSample(SensorKind.ROTATION_VECTOR, 0, 0f, 0f, 2 * h, 3, 2 * h, headingAccuracyRad = 0.05f))
        p.onSample(SensorSample(SensorKind.GAME_ROTATION_VECTOR, 0, 0f, 0f, 0f, 3, 1f))
        val st = p.snapshot()
        val rv = st.rotationVector!!
        assertEquals(1.0, rv.norm(), 1e-6)
        assertEquals(0.0, Readout.angleBetweenDeg(rv, Quaternion.fromAxisAngle(Vector3.UNIT_Z, Math.PI / 2)), 1e-4)
        assertEquals(Quaternion(1.0, 0.0, 0.0, 0.0), st.gameRotationVector)
        assertEquals(0.05, st.rotationVectorHeadingAccuracyRad!!, 1e-7)
        p.onSample(SensorSample(SensorKind.ROTATION_VECTOR, 1, 0f, 0f, 0f, 3, 1f, headingAccuracyRad = -1f))
        assertNull(p.snapshot().rotationVectorHeadingAccuracyRad, "−1: unknown")
    }

    @Test
    fun `per-sensor rate, accuracy and last values are published`() {
        val p = FusionPipeline(all, LiveSettings())
        for (i in 0..50) p.onSample(mag(i * 20 * ms, 30f, 0f, -40f, accuracy = 1))
        val m = p.snapshot().sensors.getValue(SensorKind.MAGNETOMETER)
        assertEquals(51L, m.samples)
        assertEquals(50.0, m.rateHz, 1e-9)
        assertEquals(1, m.accuracy)
        assertEquals(50.0, p.snapshot().magneticFieldUt!!, 1e-6)
        assertFalse(SensorKind.GYROSCOPE in p.snapshot().sensors)
    }

    @Test
    fun `new filter settings rebuild the filter, a new convention does not`() {
        val p = FusionPipeline(all, LiveSettings())
        val f0 = p.filter
        p.reconfigure(LiveSettings(convention = AngleConvention.AEROSPACE))
        assertSame(f0, p.filter)
        p.reconfigure(LiveSettings(filter = FilterSettings(beta = 0.1), convention = AngleConvention.AEROSPACE))
        assertNotSame(f0, p.filter)
        assertEquals(0.1, p.filter.settings.beta)
        p.reconfigure(LiveSettings(filter = FilterSettings(mode = FilterMode.IMU)))
        assertEquals(FilterMode.IMU, p.filter.settings.mode)
        assertEquals(FusionMode.IMU, p.mode.mode)
    }

    @Test
    fun `9D without magnetometer runs the filter in 6D`() {
        val p = FusionPipeline(setOf(SensorKind.ACCELEROMETER, SensorKind.GYROSCOPE), LiveSettings(filter = FilterSettings(mode = FilterMode.MARG)))
        assertEquals(EffectiveMode(FusionMode.IMU, ModeReason.NO_MAGNETOMETER), p.mode)
        assertEquals(FilterMode.IMU, p.filter.settings.mode)
    }

    @Test
    fun `effective modes for every combination of sensors`() {
        val a = SensorKind.ACCELEROMETER
        val g = SensorKind.GYROSCOPE
        val m = SensorKind.MAGNETOMETER
        assertEquals(EffectiveMode(FusionMode.MARG, ModeReason.AS_CHOSEN), effectiveMode(setOf(a, g, m), FilterMode.MARG))
        assertEquals(EffectiveMode(FusionMode.IMU, ModeReason.AS_CHOSEN), effectiveMode(setOf(a, g, m), FilterMode.IMU))
        assertEquals(EffectiveMode(FusionMode.IMU, ModeReason.NO_MAGNETOMETER), effectiveMode(setOf(a, g), FilterMode.MARG))
        assertEquals(EffectiveMode(FusionMode.ACC_MAG, ModeReason.NO_GYROSCOPE), effectiveMode(setOf(a, m), FilterMode.MARG))
        assertEquals(EffectiveMode(FusionMode.ACC_MAG, ModeReason.NO_GYROSCOPE), effectiveMode(setOf(a, m), FilterMode.IMU))
        assertEquals(EffectiveMode(FusionMode.TILT_ONLY, ModeReason.NO_GYROSCOPE_NO_MAGNETOMETER), effectiveMode(setOf(a), FilterMode.MARG))
        assertEquals(EffectiveMode(FusionMode.NONE, ModeReason.NO_ACCELEROMETER), effectiveMode(setOf(g, m), FilterMode.MARG))
        assertTrue(FusionMode.ACC_MAG.hasMagneticHeading)
        assertFalse(FusionMode.IMU.hasMagneticHeading)
    }
}
