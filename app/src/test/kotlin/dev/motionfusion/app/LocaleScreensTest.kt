package dev.motionfusion.app

import android.app.Activity
import android.hardware.Sensor
import android.hardware.SensorManager
import android.view.View
import android.view.ViewGroup
import android.widget.TextView
import com.google.android.material.slider.Slider
import dev.motionfusion.app.build.BuildFiles
import dev.motionfusion.app.calibration.CalibrationActivity
import dev.motionfusion.app.live.LiveScreen
import dev.motionfusion.app.sessions.SessionItem
import dev.motionfusion.app.sessions.SessionSummary
import dev.motionfusion.app.sessions.SessionsActivity
import dev.motionfusion.app.sessions.SessionsUiState
import dev.motionfusion.app.sessions.StreamSummary
import dev.motionfusion.app.settings.SettingsActivity
import dev.motionfusion.app.ui.AttitudeIndicatorView
import dev.motionfusion.app.ui.CompassView
import org.junit.Assert.assertEquals
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
import java.io.File
import javax.xml.parsers.DocumentBuilderFactory

/**
 * The screens in the second language the app ships (German), rendered to
 * target/screenshots/de-*.png with the layout and accessibility checks of every screen: every text
 * comes from the German resources (no word of the English texts that German lacks is on screen),
 * numbers have the German decimal comma; and the live screen's instruments and plot at twice the font size.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class LocaleScreensTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        // Names without English words: they are the device's, shown as they come.
        for ((type, name) in listOf(
            Sensor.TYPE_ACCELEROMETER to "BMI260 ACC", Sensor.TYPE_GYROSCOPE to "BMI260 GYR",
            Sensor.TYPE_MAGNETIC_FIELD to "AK09918", Sensor.TYPE_ROTATION_VECTOR to "RV 2.0",
        )) sm.addSensor(SensorBuilder.newBuilder().setType(type).setName(name).build())
        graph = TestGraph()
    }

    private val phone = "w400dp-h860dp-port-notnight-xhdpi"

    /** Words of the English texts that no German text has (4 letters or more): one on a German screen is an untranslated text. */
    private val englishOnly: Set<String> by lazy {
        fun words(dir: String): Set<String> {
            val out = HashSet<String>()
            for (f in File(BuildFiles.repositoryRoot, "app/src/main/res/$dir").listFiles()!!.filter { it.name.startsWith("strings") }) {
                val text = DocumentBuilderFactory.newInstance().newDocumentBuilder().parse(f).documentElement.textContent
                out += WORD.findAll(text).map { it.value.lowercase() }
            }
            return out
        }
        words("values") - words("values-de")
    }

    /** The texts and descriptions on [a]'s screen that hold an English word. */
    private fun english(a: Activity): List<String> {
        val out = ArrayList<String>()
        fun walk(v: View) {
            if (v.visibility != View.VISIBLE) return
            for (t in listOfNotNull((v as? TextView)?.text, v.contentDescription)) {
                val found = WORD.findAll(t).map { it.value.lowercase() }.filter { it in englishOnly }.toList()
                if (found.isNotEmpty()) out += "'$t': $found"
            }
            if (v is ViewGroup) for (i in 0 until v.childCount) walk(v.getChildAt(i))
        }
        walk(a.window.decorView)
        return out
    }

    private fun assertGerman(a: Activity, name: String) {
        assertTrue("$name: ${englishOnly.size} English-only words known", englishOnly.size > 200)
        assertEquals("$name: English on a German screen", "", english(a).joinToString("\n"))
    }

    @Test
    fun `the screens in German, every text translated, numbers with a decimal comma`() {
        RuntimeEnvironment.setQualifiers("de-rDE-$phone")
        val live = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        graph.settle()
        LiveStates.sway(LiveScreen(live, graph.capture.sensorInfo))
        Screenshots.captureScreen(live, "de-live-moving-phone-light")
        assertEquals("Nicken", live.getString(R.string.pitch))
        assertTrue(live.findViewById<TextView>(R.id.pitch).text.toString(), Regex("""^-?\d+,\d°$""").matches(live.findViewById<TextView>(R.id.pitch).text))
        assertGerman(live, "live")
        graph.graph.recordings.countdown.start(3) {}
        shadowOf(android.os.Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(600))
        assertEquals("Abbrechen (3)", live.findViewById<TextView>(R.id.record_toggle).text.toString())
        Screenshots.captureScreen(live, "de-live-countdown-phone-light")
        graph.graph.recordings.countdown.cancel()

        val settings = Robolectric.buildActivity(SettingsActivity::class.java).setup().get()
        graph.settle()
        settings.findViewById<android.view.View>(R.id.settings_advanced_toggle).performClick()
        settings.row("beta").findViewById<Slider>(R.id.setting_slider).value = 0.12f
        graph.settle()
        assertEquals("0,12 rad/s (6,9°/s)", settings.row("beta").findViewById<TextView>(R.id.setting_value).text.toString())
        assertEquals("Angeforderte Sensorrate", settings.row("rate").findViewById<TextView>(R.id.setting_name).text.toString())
        Screenshots.captureScreen(settings, "de-settings-phone-light")
        Screenshots.captureWhole(settings, "de-settings-phone-light-all")
        assertGerman(settings, "settings")

        val sessions = Robolectric.buildActivity(SessionsActivity::class.java).setup().get()
        graph.settle()
        val streams = listOf(StreamSummary("accelerometer", 150_800, 200.0), StreamSummary("gyroscope", 150_800, 200.0), StreamSummary("magnetometer", 75_400, 100.0))
        sessions.show(
            SessionsUiState.Loaded(
                listOf(
                    SessionItem(File("Spaziergang"), SessionSummary("Spaziergang", 1_795_688_100_000L, 754_000_000_000L, 31_668_000, streams, 150_800, recovered = true), null),
                ),
            ),
        )
        Screenshots.captureScreen(sessions, "de-sessions-list-phone-light")
        // The date as German writes it (day.month.year), whatever the JVM's own locale.
        val line = sessions.findViewById<TextView>(R.id.session_line1).text.toString()
        assertTrue(line, Regex("""\b26\.11\.2026\b""").containsMatchIn(line))
        assertGerman(sessions, "sessions")

        val calibration = Robolectric.buildActivity(CalibrationActivity::class.java).setup().get()
        graph.settle()
        Screenshots.captureScreen(calibration, "de-calibration-ready-phone-light")
        assertGerman(calibration, "calibration")
    }

    @Test
    fun `the instruments' texts follow the font size`() {
        fun instruments(scale: Float, png: String): Triple<Float, Float, Int> {
            RuntimeEnvironment.setQualifiers(phone)
            RuntimeEnvironment.setFontScale(scale)
            val a = Robolectric.buildActivity(MainActivity::class.java).setup().get()
            graph.settle()
            LiveStates.sway(LiveScreen(a, graph.capture.sensorInfo))
            Screenshots.captureWhole(a, png) // unrolled: the instruments lie below the fold at twice the font size
            Screenshots.assertAccessible(a, png)
            return Triple(a.findViewById<CompassView>(R.id.compass).labelTextPx, a.findViewById<AttitudeIndicatorView>(R.id.attitude).labelTextPx, a.findViewById<View>(R.id.plot).height)
        }
        val normal = instruments(1f, "live-moving-phone-font1")
        val large = instruments(2f, "live-moving-phone-font2")
        // Android 14+ scales large text less than linearly; 16 sp at 2× is still well over 1.5×.
        assertTrue("compass $normal → $large", large.first >= 1.5f * normal.first)
        assertTrue("attitude $normal → $large", large.second >= 1.5f * normal.second)
        // The plot grows with its axis labels, so that they do not overlap.
        assertTrue("plot $normal → $large", large.third > normal.third)
    }

    private companion object {
        val WORD = Regex("""\p{L}{4,}""")
    }
}
