package dev.motionfusion.app

import android.content.Context
import android.hardware.Sensor
import android.hardware.SensorManager
import android.view.View
import android.widget.Button
import android.widget.CompoundButton
import android.widget.TextView
import com.google.android.material.chip.Chip
import com.google.android.material.chip.ChipGroup
import com.google.android.material.slider.Slider
import dev.motionfusion.app.settings.AngleConvention
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.settings.RecordingLimits
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.app.settings.Setting
import dev.motionfusion.app.settings.SettingsActivity
import dev.motionfusion.app.settings.SettingsStore
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.settings.FilterSettingDescriptors
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.settings.SettingKind
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.android.controller.ActivityController
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.SensorBuilder

/** The settings screen: every setting of the core table, shows the settings in force, persists and applies. */
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

    private fun SettingsActivity.slider(key: String): Slider = row(key).findViewById(R.id.setting_slider)
    private fun SettingsActivity.switch(key: String): CompoundButton = row(key).findViewById(R.id.setting_switch)
    private fun SettingsActivity.text(key: String, id: Int): String = row(key).findViewById<TextView>(id).text.toString()
    private fun SettingsActivity.checkedChoice(key: String): String {
        val g = row(key).findViewById<ChipGroup>(R.id.setting_choices)
        return g.findViewById<Chip>(g.checkedChipId).tag as String
    }
    private fun SettingsActivity.choose(key: String, choice: String) {
        val g = row(key).findViewById<ChipGroup>(R.id.setting_choices)
        (0 until g.childCount).map { g.getChildAt(it) as Chip }.first { it.tag == choice }.performClick()
    }

    private var graph: TestGraph? = null
    private fun store() = SettingsStore(RuntimeEnvironment.getApplication())

    /** What is stored, once the app's writes are done. */
    private fun stored(): LiveSettings {
        graph?.settle()
        return offMainThread { store().load() }
    }

    private fun save(s: LiveSettings) = offMainThread { store().save(s) }

    /** The screen, on the app's graph made on first use (after what the test stored: the graph reads it). */
    private fun start(): ActivityController<SettingsActivity> {
        if (graph == null) graph = TestGraph()
        return Robolectric.buildActivity(SettingsActivity::class.java).setup()
    }

    @Test
    fun `every filter setting of the core table has a row with its unit and default`() {
        val a = start().get()
        val shown = FilterSettingDescriptors.all.filter { it.name != "outputFrame" }
        for (d in shown) {
            val row = a.row(d.jsonKey)
            assertEquals(d.title, (row.findViewById<TextView>(R.id.setting_name) ?: row.findViewById<TextView>(R.id.setting_switch)).text.toString())
            if (d.kind == SettingKind.NUMBER) {
                val value = a.text(d.jsonKey, R.id.setting_value)
                if (!(d.zeroDisables && d.default == null)) assertTrue("${d.name}: '$value' lacks ${d.unit}", value.contains(d.unit))
                // The default is marked, and the value shown is the default's.
                assertTrue("${d.name}: ${a.text(d.jsonKey, R.id.setting_help)}", a.text(d.jsonKey, R.id.setting_help).startsWith("Default"))
                assertEquals(d.name, ((d.default as Double?) ?: 0.0).toFloat(), a.slider(d.jsonKey).value, 1e-6f)
                assertEquals(d.name, d.zeroDisables, a.switch(d.jsonKey).visibility == View.VISIBLE)
                assertFalse("${d.name}: reset enabled at the default", a.row(d.jsonKey).findViewById<Button>(R.id.setting_reset).isEnabled)
            }
        }
        assertEquals(shown.size + Setting.APP.size, Setting.ALL.size)
        assertEquals("0.02 rad/s (1.1°/s)", a.text("beta", R.id.setting_value))
        // The saturation's default is the phone's own range (FusionPipeline), the table's value only without one.
        assertEquals(
            "Default: 97 % of this phone's gyroscope range (34 rad/s (1948.1°/s) without one; 0 turns it off)",
            a.text("gyro_saturation_rad_s", R.id.setting_help),
        )
    }

    @Test
    fun `the form shows the stored settings`() {
        save(LiveSettings(filter = FilterSettings(beta = 0.07, mode = FilterMode.IMU, gyroSaturation = null), convention = AngleConvention.AEROSPACE, rate = SamplingRate.Delay.GAME))
        val a = start().get()
        assertEquals(0.07f, a.slider("beta").value, 1e-6f)
        assertEquals("0.07 rad/s (4.0°/s)", a.text("beta", R.id.setting_value))
        assertEquals("IMU", a.checkedChoice("mode"))
        assertEquals("AEROSPACE", a.checkedChoice("convention"))
        assertEquals("game", a.checkedChoice("rate"))
        assertFalse(a.switch("gyro_saturation_rad_s").isChecked)
        assertFalse(a.slider("gyro_saturation_rad_s").isEnabled)
        assertEquals("off", a.text("gyro_saturation_rad_s", R.id.setting_value))
    }

    @Test
    fun `sliders, switches and choices are persisted and change the filter`() {
        val a = start().get()
        a.slider("beta").value = 0.1f
        a.switch("zeta").isChecked = true // off by default: on gives a tenth of its range
        a.switch("heading_gain_1_s").isChecked = false
        a.row("acc_rejection").findViewById<CompoundButton>(R.id.setting_switch).isChecked = true
        a.choose("mode", "IMU")
        a.choose("rate", "hz:400")
        assertEquals("1 h", dev.motionfusion.app.settings.SettingText.label(a, Setting.ALL.first { it.key == Setting.MAX_DURATION }, "3600"))
        a.choose(Setting.MAX_DURATION, "3600")
        a.choose(Setting.STOP_BATTERY, "15")
        assertEquals("3 s", dev.motionfusion.app.settings.SettingText.label(a, Setting.ALL.first { it.key == Setting.START_DELAY }, "3"))
        a.choose(Setting.START_DELAY, "3")
        a.switch("record_rotation_vector").isChecked = false
        // No Apply: each change is in force at once.
        val expected = LiveSettings(
            filter = FilterSettings(beta = 0.1, zeta = 0.005, headingGain = null, mode = FilterMode.IMU, accRejection = true),
            rate = SamplingRate.Hz(400),
            limits = RecordingLimits(maxDurationS = 3600L, stopBatteryPercent = 15),
            startDelayS = 3,
            optionalStreams = LiveSettings.OPTIONAL_STREAMS - dev.motionfusion.core.event.SessionStream.ROTATION_VECTOR,
        )
        assertEquals(expected, stored())
        val graph = (a.application as MotionFusionApp).graph
        assertEquals(expected, graph.settingsRepository.settings.value)
        shadowOf(android.os.Looper.getMainLooper()).idle()
        val fs = graph.capture.filterSettingsInUse()
        assertEquals(0.1, fs.beta, 0.0)
        assertEquals(0.005, fs.zeta!!, 0.0)
        assertNull(fs.headingGain)
        assertEquals(FilterMode.IMU, fs.mode)
        assertTrue(fs.accRejection)
        assertEquals("", a.findViewById<TextView>(R.id.settings_message).text.toString())
        // Turned on again, a setting gets back the value it had.
        a.switch("heading_gain_1_s").isChecked = true
        assertEquals(FilterSettings().headingGain!!.toFloat(), a.slider("heading_gain_1_s").value, 1e-6f)
    }

    @Test
    fun `Walking through buildings turns the magnetic trust on with the buildings' value and keeps one set under Advanced`() {
        val a = start().get()
        assertFalse(a.switch(Setting.BUILDINGS).isChecked)
        assertEquals("Heading", (a.row(Setting.BUILDINGS).parent as View).findViewById<TextView>(R.id.section_title).text.toString())
        a.switch(Setting.BUILDINGS).isChecked = true
        assertEquals(FilterSettings(magTrustSpread = FilterSettings.BUILDINGS_TRUST_SPREAD), stored().filter)
        shadowOf(android.os.Looper.getMainLooper()).idle()
        assertEquals(FilterSettings.BUILDINGS_TRUST_SPREAD, graph!!.graph.capture.filterSettingsInUse().magTrustSpread!!, 0.0)
        // The same setting under Advanced shows it, and a value chosen there is kept by the switch.
        assertTrue(a.switch("mag_trust_spread").isChecked)
        assertEquals(FilterSettings.BUILDINGS_TRUST_SPREAD.toFloat(), a.slider("mag_trust_spread").value, 1e-6f)
        Screenshots.captureWhole(a, "settings-buildings-on-phone-light")
        a.slider("mag_trust_spread").value = 0.01f
        assertTrue(a.switch(Setting.BUILDINGS).isChecked)
        assertEquals(0.01, stored().filter.magTrustSpread!!, 1e-6)
        a.switch(Setting.BUILDINGS).isChecked = false
        assertNull(stored().filter.magTrustSpread)
        assertFalse(a.switch("mag_trust_spread").isChecked)
        a.switch(Setting.BUILDINGS).isChecked = true
        assertEquals(FilterSettings.BUILDINGS_TRUST_SPREAD, stored().filter.magTrustSpread!!, 0.0)
        // Stored, both keys agree; read back in either order they give the same settings.
        val s = stored()
        assertEquals("true", offMainThread { RuntimeEnvironment.getApplication().getSharedPreferences(SettingsStore.FILE, Context.MODE_PRIVATE).getString(Setting.BUILDINGS, null) })
        assertEquals(s, offMainThread { SettingsStore({ RuntimeEnvironment.getApplication().getSharedPreferences(SettingsStore.FILE, Context.MODE_PRIVATE) }, Setting.ALL.reversed()).load() })
    }

    @Test
    fun `reset puts one setting back, Defaults all of them`() {
        val a = start().get()
        a.slider("beta").value = 0.3f
        a.slider("rest_min_time_s").value = 4f
        val reset = a.row("beta").findViewById<Button>(R.id.setting_reset)
        assertTrue(reset.isEnabled)
        reset.performClick()
        assertEquals(0.02f, a.slider("beta").value, 1e-6f)
        assertEquals(4f, a.slider("rest_min_time_s").value, 1e-6f)
        a.findViewById<View>(R.id.reset).performClick()
        assertEquals(1.5f, a.slider("rest_min_time_s").value, 1e-6f)
        assertEquals(LiveSettings(), stored())
        // Defaults are undone as one change: both values come back.
        shadowOf(android.os.Looper.getMainLooper()).idle()
        assertEquals("Every setting back to its default", snackbarText(a))
        undo(a)
        assertEquals(4f, a.slider("rest_min_time_s").value, 1e-6f)
        assertEquals(0.02f, a.slider("beta").value, 1e-6f)
        assertEquals(4.0, stored().filter.restMinTime, 1e-9)
    }

    @Test
    fun `a change is in force at once, kept through a rotation, and undone`() {
        val c = start()
        c.get().slider("beta").value = 0.2f
        c.get().slider("beta").value = 0.25f // a slider dragged: one change for Undo
        assertEquals(0.25, stored().filter.beta, 1e-6)
        assertEquals(0.25, graph!!.graph.settingsRepository.settings.value.filter.beta, 1e-6)
        shadowOf(android.os.Looper.getMainLooper()).idle()
        assertEquals("“β, correction gain” changed", snackbarText(c.get()))
        c.recreate()
        val a = c.get()
        assertEquals(0.25f, a.slider("beta").value, 1e-6f)
        // The filter's tuning is folded away until opened, and stays as the user left it through the rotation.
        assertEquals(View.GONE, a.findViewById<View>(R.id.settings_advanced).visibility)
        a.findViewById<View>(R.id.settings_advanced_toggle).performClick()
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.settings_advanced).visibility)
        c.recreate()
        assertEquals(View.VISIBLE, c.get().findViewById<View>(R.id.settings_advanced).visibility)
        c.get().slider("beta").value = 0.3f
        shadowOf(android.os.Looper.getMainLooper()).idle()
        undo(c.get())
        // Undo gives back what was in force before the last change.
        assertEquals(0.25f, c.get().slider("beta").value, 1e-6f)
        assertEquals(0.25, stored().filter.beta, 1e-6)
    }

    private fun snackbarText(a: SettingsActivity): String =
        a.snackbar!!.view.findViewById<TextView>(com.google.android.material.R.id.snackbar_text).text.toString()

    private fun undo(a: SettingsActivity) {
        a.snackbar!!.view.findViewById<Button>(com.google.android.material.R.id.snackbar_action).performClick()
        shadowOf(android.os.Looper.getMainLooper()).idle()
    }

    /** Back on [a]: the system's (or the app bar's Up, which goes the same way). */
    private fun back(a: SettingsActivity) {
        a.onBackPressedDispatcher.onBackPressed()
        shadowOf(android.os.Looper.getMainLooper()).idle()
    }

    @Test
    fun `Back leaves at once, every change already in force`() {
        val a = start().get()
        a.slider("beta").value = 0.25f
        back(a)
        assertTrue("no question: nothing is left unapplied", a.isFinishing)
        assertEquals(0.25, stored().filter.beta, 1e-6)
        assertEquals(0.25, graph!!.graph.settingsRepository.settings.value.filter.beta, 1e-6)
        // The app bar's Up goes the same way.
        val b = start().get()
        b.onSupportNavigateUp()
        shadowOf(android.os.Looper.getMainLooper()).idle()
        assertTrue(b.isFinishing)
    }

    @Test
    fun `a damaged or older settings file loses nothing it can read`() {
        val prefs = offMainThread { RuntimeEnvironment.getApplication().getSharedPreferences(SettingsStore.FILE, Context.MODE_PRIVATE) }
        // The first settings screen stored flags as booleans under shorter keys.
        offMainThread {
            prefs.edit().putString("beta", "0.04").putString("zeta", "NaN").putBoolean("rest_bias", false).putBoolean("acc_rejection", true)
                .putString("rest_min_time_s", "-3").putString("rate", "hz:137").putString("mode", "6D").commit()
        }
        val s = stored()
        assertEquals(LiveSettings(filter = FilterSettings(beta = 0.04, restBiasEstimation = false, accRejection = true), rate = SamplingRate.Hz(137)), s)
        // A rate outside the offered choices is still offered and shown.
        val a = start().get()
        assertEquals("hz:137", a.checkedChoice("rate"))
        save(s)
        assertEquals(s, stored())
        assertFalse(offMainThread { prefs.contains("rest_bias") })
    }

    @Test
    fun `a phone upgraded with mechanisms stored off as 0 keeps them off, and shows and stores them so`() {
        val prefs = offMainThread { RuntimeEnvironment.getApplication().getSharedPreferences(SettingsStore.FILE, Context.MODE_PRIVATE) }
        // As every version before null-for-off stored them: a mechanism off as the number 0.
        offMainThread {
            prefs.edit().putString("heading_gain_1_s", "0.0").putString("gyro_saturation_rad_s", "0.0").putString("acc_low_pass_time_s", "0")
                .putString("mag_trust_spread", "0.01").putString("zeta", "0.0").putString("beta", "0.04").commit()
        }
        val s = stored()
        assertEquals(LiveSettings(filter = FilterSettings(beta = 0.04, headingGain = null, gyroSaturation = null, accLowPassTime = null, magTrustSpread = 0.01)), s)
        val a = start().get()
        for (key in listOf("heading_gain_1_s", "gyro_saturation_rad_s", "acc_low_pass_time_s", "zeta")) {
            assertEquals(key, "off", a.text(key, R.id.setting_value))
            assertFalse(key, a.switch(key).isChecked)
        }
        assertTrue(a.switch("mag_trust_spread").isChecked)
        Screenshots.captureWhole(a, "settings-upgraded-off-phone-light-all")
        // Saved again, off is still the 0 an older version reads back.
        save(s)
        assertEquals("0.0", offMainThread { prefs.getString("heading_gain_1_s", null) })
        assertEquals("0.01", offMainThread { prefs.getString("mag_trust_spread", null) })
        assertEquals(s, stored())
    }
}
