package dev.motionfusion.app.settings

import dev.motionfusion.app.live.AngleConvention
import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.core.filter.FilterMode
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Test

/** Validation of the settings form, on the JVM. */
class SettingsFormTest {
    @Test
    fun `a form shows settings that parse back to the same settings`() {
        val cases = listOf(
            LiveSettings(),
            LiveSettings(beta = 0.1, zeta = 0.015, mode = FilterMode.IMU, restBiasEstimation = false, accRejection = true,
                convention = AngleConvention.AEROSPACE, rate = SamplingRate.Delay.FASTEST),
            LiveSettings(rate = SamplingRate.Hz(400)),
        )
        for (s in cases) assertEquals(SettingsForm.Result.Valid(s), SettingsForm.of(s).parse())
    }

    @Test
    fun `bad numbers are reported per field`() {
        val f = SettingsForm.of(LiveSettings()).copy(beta = "-1", zeta = "x", delay = null, rateHz = "5000")
        val r = f.parse() as SettingsForm.Result.Invalid
        assertEquals(setOf(SettingsField.BETA, SettingsField.ZETA, SettingsField.RATE_HZ), r.errors.keys)
        val r2 = SettingsForm.of(LiveSettings()).copy(beta = "NaN").parse() as SettingsForm.Result.Invalid
        assertEquals(setOf(SettingsField.BETA), r2.errors.keys)
    }

    @Test
    fun `a decimal comma is accepted and the Hz field is ignored for a named delay`() {
        val f = SettingsForm.of(LiveSettings()).copy(beta = " 0,05 ", delay = SamplingRate.Delay.GAME, rateHz = "junk")
        val s = (f.parse() as SettingsForm.Result.Valid).settings
        assertEquals(0.05, s.beta)
        assertEquals(SamplingRate.Delay.GAME, s.rate)
        assertEquals(0.05, s.filterSettings().beta)
    }

    @Test
    fun `settings refuse out-of-range values themselves`() {
        assertThrows(IllegalArgumentException::class.java) { LiveSettings(beta = Double.NaN) }
        assertThrows(IllegalArgumentException::class.java) { LiveSettings(zeta = 2.0) }
    }
}
