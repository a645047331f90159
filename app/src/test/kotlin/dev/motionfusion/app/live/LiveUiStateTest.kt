package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sensor.SensorSample
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.fusion.FusionPipeline

/** One frame's UI state from a fusion state: warnings, heading quality, the comparison. */
class LiveUiStateTest {
    private val all = SensorKind.entries.toSet()
    private val ms = 1_000_000L

    private fun flatNorth(p: FusionPipeline, magAccuracy: Int = 3, mag: FloatArray = floatArrayOf(0f, 22f, -40f)) {
        for (i in 0..5) {
            p.onSample(SensorSample(SensorKind.ACCELEROMETER, i * 10 * ms, 0f, 0f, 9.81f, 3))
            p.onSample(SensorSample(SensorKind.MAGNETOMETER, i * 10 * ms, mag[0], mag[1], mag[2], magAccuracy))
            p.onSample(SensorSample(SensorKind.GYROSCOPE, i * 10 * ms, 0f, 0f, 0f, 3))
        }
    }

    @Test
    fun `a calibrated magnetometer in the Earth's field gives no warning`() {
        val p = FusionPipeline(all, LiveSettings())
        flatNorth(p)
        val ui = LiveUiState.of(p.snapshot(), 0)
        assertTrue(ui.magWarnings.isEmpty())
        assertFalse(ui.showCalibrationHint)
        assertEquals(HeadingQuality.OK, ui.headingQuality)
        assertEquals(0.0, ((ui.headingDeg!! + 180.0) % 360.0) - 180.0, 0.05)
    }

    @Test
    fun `low accuracy and a strong field warn and ask for a figure 8`() {
        val p = FusionPipeline(all, LiveSettings())
        flatNorth(p, magAccuracy = 1, mag = floatArrayOf(0f, 60f, -70f))
        val ui = LiveUiState.of(p.snapshot(), 0)
        assertEquals(setOf(MagWarning.LOW_ACCURACY, MagWarning.FIELD_STRENGTH), ui.magWarnings)
        assertTrue(ui.showCalibrationHint)
        assertEquals(HeadingQuality.WARNING, ui.headingQuality)
    }

    /** Level and still for 40 s, in a field whose strength wanders by up to ±15 % (a building's steel passing by). */
    private fun wanderingField(p: FusionPipeline) {
        for (i in 0..4000) {
            val t = i * 10 * ms
            val k = (1.0 + 0.15 * kotlin.math.sin(i * 0.02) * kotlin.math.sin(i * 0.0071)).toFloat()
            p.onSample(SensorSample(SensorKind.ACCELEROMETER, t, 0f, 0f, 9.81f, 3))
            p.onSample(SensorSample(SensorKind.MAGNETOMETER, t, 0f, 22f * k, -40f * k, 3))
            p.onSample(SensorSample(SensorKind.GYROSCOPE, t, 0f, 0f, 0f, 3))
        }
    }

    @Test
    fun `walking through a building with the switch on says the heading is held on the gyroscope, without a figure 8`() {
        val p = FusionPipeline(all, LiveSettings(filter = FilterSettings(magTrustSpread = FilterSettings.BUILDINGS_TRUST_SPREAD)))
        wanderingField(p)
        val ui = LiveUiState.of(p.snapshot(), 0)
        assertEquals(setOf(MagWarning.DISTURBED), ui.magWarnings)
        assertFalse(ui.showCalibrationHint)
        // The same field with the switch off: nothing held.
        val off = FusionPipeline(all, LiveSettings())
        wanderingField(off)
        assertTrue(LiveUiState.of(off.snapshot(), 0).magWarnings.isEmpty())
    }

    @Test
    fun `in 6D the heading is relative and the magnetometer is not judged`() {
        val p = FusionPipeline(all, LiveSettings(filter = FilterSettings(mode = FilterMode.IMU)))
        flatNorth(p, magAccuracy = 0)
        val ui = LiveUiState.of(p.snapshot(), 0)
        assertEquals(HeadingQuality.RELATIVE, ui.headingQuality)
        assertTrue(ui.magWarnings.isEmpty())
    }

    @Test
    fun `the rotation vector is compared by total angle and by tilt`() {
        val p = FusionPipeline(all, LiveSettings())
        flatNorth(p)
        // The phone's rotation vector says: top 10° east of north (−10° about up).
        val h = Math.toRadians(-10.0) / 2
        p.onSample(SensorSample(SensorKind.ROTATION_VECTOR, 60 * ms, 0f, 0f, Math.sin(h).toFloat(), 3, Math.cos(h).toFloat()))
        val ui = LiveUiState.of(p.snapshot(), 0)
        // Within 0.05°: the filter's own estimate chatters that close to the truth (FusionPipelineTest).
        assertEquals(10.0, ui.differenceDeg!!, 0.05)
        assertEquals(0.0, ui.tiltDifferenceDeg!!, 0.05)
        assertEquals(10.0, ui.rotationVectorAngles!!.yaw, 1e-4)
        assertNull(ui.gameTiltDifferenceDeg)
    }

    @Test
    fun `nothing to show before the first orientation`() {
        val ui = LiveUiState.of(FusionPipeline(all, LiveSettings()).snapshot(), 0)
        assertNull(ui.angles)
        assertNull(ui.headingDeg)
        assertEquals(HeadingQuality.NONE, ui.headingQuality)
    }
}
