package dev.motionfusion.app

import android.hardware.Sensor
import android.hardware.SensorManager
import android.widget.EditText
import android.widget.RadioGroup
import android.widget.CompoundButton
import android.view.View
import com.google.android.material.slider.Slider
import android.widget.TextView
import dev.motionfusion.app.live.AngleConvention
import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.settings.SettingsActivity
import dev.motionfusion.app.settings.SettingsStore
import dev.motionfusion.core.filter.FilterMode
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNotNull
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.SensorBuilder

/** The settings screen: shows the settings in force, validates, persists and applies. */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class SettingsActivityTest {
    @Before
    fun sensors() {
        val sm = shadowOf(RuntimeEnvironment.getApplication().getSystemService(SensorManager::class.java))
        for (type in listOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE, Sensor.TYPE_MAGNETIC_FIELD)) {
            sm.addSensor(SensorBuilder.newBuilder().setType(type).build())
        }
    }

    private fun SettingsActivity.slider(setting: Int): Slider = findViewById<View>(setting).findViewById(R.id.setting_slider)

    private fun store() = SettingsStore(RuntimeEnvironment.getApplication())

    @Test
    fun `the form shows the stored settings`() {
        store().save(LiveSettings(beta = 0.07, mode = FilterMode.IMU, convention = AngleConvention.AEROSPACE, rate = SamplingRate.Delay.GAME))
        val a = Robolectric.buildActivity(SettingsActivity::class.java).setup().get()
        assertEquals(0.07f, a.slider(R.id.beta_setting).value, 1e-6f)
        assertEquals("0.07 rad/s", a.findViewById<View>(R.id.beta_setting).findViewById<TextView>(R.id.setting_value).text.toString())
        assertFalse(a.findViewById<CompoundButton>(R.id.nine_d).isChecked)
        assertEquals(R.id.convention_aerospace, a.findViewById<RadioGroup>(R.id.convention).checkedRadioButtonId)
        assertEquals(R.id.rate_game, a.findViewById<RadioGroup>(R.id.rate).checkedRadioButtonId)
        Screenshots.capture(a, "settings")
    }

    @Test
    fun `invalid entries are marked and nothing is saved`() {
        val a = Robolectric.buildActivity(SettingsActivity::class.java).setup().get()
        a.findViewById<RadioGroup>(R.id.rate).check(R.id.rate_hz)
        a.findViewById<EditText>(R.id.rate_hz_value).setText("0")
        assertFalse(a.apply())
        assertNotNull(a.findViewById<EditText>(R.id.rate_hz_value).error)
        assertNull(a.findViewById<View>(R.id.beta_setting).findViewById<TextView>(R.id.setting_help).error)
        assertEquals(a.getString(R.string.settings_invalid), a.findViewById<TextView>(R.id.settings_message).text.toString())
        assertEquals(LiveSettings(), store().load())
        Screenshots.capture(a, "settings-invalid")
    }

    @Test
    fun `valid entries are persisted and change the filter`() {
        val a = Robolectric.buildActivity(SettingsActivity::class.java).setup().get()
        a.slider(R.id.beta_setting).value = 0.1f
        a.slider(R.id.zeta_setting).value = 0.01f
        a.findViewById<CompoundButton>(R.id.nine_d).isChecked = false
        a.findViewById<CompoundButton>(R.id.acc_rejection).isChecked = true
        a.findViewById<RadioGroup>(R.id.rate).check(R.id.rate_hz)
        a.findViewById<EditText>(R.id.rate_hz_value).setText("400")
        assertTrue(a.apply())
        val expected = LiveSettings(beta = 0.1, zeta = 0.01, mode = FilterMode.IMU, accRejection = true, rate = SamplingRate.Hz(400))
        assertEquals(expected, store().load())
        val graph = (a.application as MotionFusionApp).graph
        assertEquals(expected, graph.settingsRepository.settings.value)
        org.robolectric.Shadows.shadowOf(android.os.Looper.getMainLooper()).idle()
        val fs = graph.capture.filterSettingsInUse()
        assertEquals(0.1, fs.beta, 0.0)
        assertEquals(0.01, fs.zeta, 0.0)
        assertEquals(FilterMode.IMU, fs.mode)
        assertTrue(fs.accRejection)
    }
}
