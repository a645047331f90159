package dev.motionfusion.app

import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.widget.CompoundButton
import androidx.appcompat.app.AlertDialog
import dev.motionfusion.app.calibration.CalibrationActivity
import dev.motionfusion.app.live.LiveScreen
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.sessions.SessionDetailActivity
import dev.motionfusion.app.sessions.SessionsActivity
import dev.motionfusion.app.sessions.SessionsUiState
import dev.motionfusion.app.settings.SettingsActivity
import dev.motionfusion.app.stream.StreamActivity
import dev.motionfusion.app.stream.StreamState
import dev.motionfusion.core.session.Marker
import org.junit.After
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
import org.robolectric.shadows.ShadowDialog
import java.io.File

/**
 * Every screen, and the dialogs a user meets on the way, at the font sizes Android offers above the
 * default (1.3 and 2.0) and in a right-to-left language (Arabic: the app has no Arabic texts, so
 * English laid out from the right, with Arabic digits where the app formats numbers), rendered to
 * target/screenshots/VARIANT-SCREEN.png with the layout and accessibility checks of every screenshot
 * (texts inside the screen, none cut short or overlapping; touch targets, labels, contrast). Long
 * screens are also rendered unrolled (…-all.png). One API level: nothing here depends on the version.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class ScaledScreensTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    /** A variant: its file-name prefix, the qualifiers (a phone held upright) and the font scale. */
    private enum class Variant(val qualifiers: String, val fontScale: Float) {
        FONT13("w400dp-h860dp-port-notnight-xhdpi", 1.3f),
        FONT2("w400dp-h860dp-port-notnight-xhdpi", 2f),
        RTL("ar-ldrtl-w400dp-h860dp-port-notnight-xhdpi", 1f),
        ;

        val prefix get() = name.lowercase()
    }

    private fun configure(v: Variant) {
        RuntimeEnvironment.setQualifiers(v.qualifiers)
        RuntimeEnvironment.setFontScale(v.fontScale)
    }

    @Before
    fun setUp() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        for ((type, name) in listOf(
            Sensor.TYPE_ACCELEROMETER to "BMI260 Accelerometer", Sensor.TYPE_GYROSCOPE to "BMI260 Gyroscope",
            Sensor.TYPE_MAGNETIC_FIELD to "AK09918 Magnetometer", Sensor.TYPE_ROTATION_VECTOR to "Rotation Vector",
        )) sm.addSensor(SensorBuilder.newBuilder().setType(type).setName(name).build())
        graph = TestGraph()
        shadowOf(app).grantPermissions(android.Manifest.permission.POST_NOTIFICATIONS)
    }

    @After
    fun tearDown() {
        graph.graph.stream.stop()
        graph.settle()
    }

    private fun sessionsRoot(): File = offMainThread { graph.graph.sessions.root() }

    /** [a] on screen, and unrolled when it scrolls. */
    private fun render(a: android.app.Activity, name: String, whole: Boolean = false) {
        graph.settle()
        Screenshots.captureScreen(a, name)
        if (whole) Screenshots.captureWhole(a, "$name-all")
    }

    private fun dialog(a: android.app.Activity, name: String): AlertDialog {
        shadowOf(Looper.getMainLooper()).idle()
        val d = ShadowDialog.getLatestDialog() as AlertDialog
        assertTrue(name, d.isShowing)
        Screenshots.captureDialog(a, d, name)
        return d
    }

    @Test
    fun `live screen, recording, and the Stop question`() {
        for (v in Variant.entries) {
            configure(v)
            graph.graph.recordings.set(RecordingState.Idle)
            val a = Robolectric.buildActivity(MainActivity::class.java).setup().get()
            graph.settle()
            LiveStates.sway(LiveScreen(a, graph.capture.sensorInfo))
            render(a, "${v.prefix}-live-moving", whole = true)
            // Record with a start delay: the countdown, cancellable.
            graph.graph.recordings.countdown.start(10) {}
            shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(1_500))
            assertEquals(a.getString(R.string.record_countdown, 9), a.findViewById<android.widget.TextView>(R.id.record_status).text.toString())
            render(a, "${v.prefix}-live-countdown")
            graph.graph.recordings.countdown.cancel()

            graph.graph.recordings.set(
                RecordingState.Active(
                    File(sessionsRoot(), "session_2026-12-01_18-40-00"), graph.clock.elapsedNs / 1_000_000 - 83_000, rows = { 41_522L },
                    markers = { listOf(Marker(5_200_000_000L, "start walk")) }, streams = 4,
                ),
            )
            shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(1))
            render(a, "${v.prefix}-live-recording")
            a.findViewById<View>(R.id.record_toggle).performClick()
            dialog(a, "${v.prefix}-live-stop-confirm").dismiss()
        }
    }

    /**
     * Numbers in Arabic digits stand isolated (LRI … PDI) in [text]: joined by separators and units they were
     * reordered ("150,800 · 200.0 Hz" shown as "200.0 · 150,800 Hz", "50 Hz" as "Hz 50").
     */
    private fun assertNumbersIsolated(text: String) {
        val outside = text.replace(Regex("\u2066[^\u2069]*\u2069"), "")
        assertTrue("a number in Arabic digits not isolated: $text", outside.none { it in '\u0660'..'\u0669' })
    }

    @Test
    fun `sessions list and session detail`() {
        val root = sessionsRoot()
        val items = SessionStates.items(root)
        val name = "walk to the station"
        offMainThread { File(root, name).mkdirs() }
        for (v in Variant.entries) {
            configure(v)
            val list = Robolectric.buildActivity(SessionsActivity::class.java).setup().get()
            graph.settle()
            list.show(SessionsUiState.Loaded(items))
            render(list, "${v.prefix}-sessions-list")
            assertNumbersIsolated(list.findViewById<android.widget.TextView>(R.id.session_line2).text.toString())

            val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, name)
            val detail = Robolectric.buildActivity(SessionDetailActivity::class.java, intent).setup().get()
            graph.settle()
            detail.show(SessionStates.detail(name))
            render(detail, "${v.prefix}-session-detail", whole = true)
            assertNumbersIsolated(detail.findViewById<android.widget.TextView>(R.id.detail_streams).text.toString())
        }
    }

    @Test
    fun `settings, folded and open, and a change with its Undo`() {
        for (v in Variant.entries) {
            configure(v)
            graph.graph.settingsRepository.update(dev.motionfusion.app.settings.LiveSettings()) // the last variant's change undone
            val a = Robolectric.buildActivity(SettingsActivity::class.java).setup().get()
            graph.settle()
            render(a, "${v.prefix}-settings", whole = true)
            a.findViewById<android.view.View>(R.id.settings_advanced_toggle).performClick()
            graph.settle()
            render(a, "${v.prefix}-settings-advanced", whole = true)
            // Changed: applied at once, the snackbar offers Undo.
            a.row(dev.motionfusion.app.settings.Setting.START_DELAY).findViewById<com.google.android.material.chip.ChipGroup>(R.id.setting_choices)
                .let { g -> (0 until g.childCount).map { g.getChildAt(it) }.first { it.tag == "10" }.performClick() }
            graph.settle()
            shadowOf(android.os.Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(500)) // the snackbar slides in
            render(a, "${v.prefix}-settings-undo")
            assertTrue(a.snackbar!!.isShown)
        }
    }

    @Test
    fun `stream, off and on`() {
        for (v in Variant.entries) {
            configure(v)
            val a = Robolectric.buildActivity(StreamActivity::class.java).setup().get()
            graph.settle()
            render(a, "${v.prefix}-stream-off")
            a.findViewById<CompoundButton>(R.id.stream_switch).performClick()
            graph.settle()
            assertTrue(graph.graph.stream.state.value.toString(), graph.graph.stream.state.value is StreamState.On)
            render(a, "${v.prefix}-stream-on", whole = true)
            // The address as a laptop takes it: ASCII digits also on an Arabic phone.
            val address = a.findViewById<android.widget.TextView>(R.id.stream_addresses).text.toString()
            assertTrue("${v.prefix}: $address", Regex("""^ws://192\.168\.1\.23:[0-9]+$""").matches(address))
            val usb = a.findViewById<android.widget.TextView>(R.id.stream_usb).text.toString()
            assertTrue("${v.prefix}: $usb", Regex("""^adb forward tcp:([0-9]+) tcp:\1, then ws://127\.0\.0\.1:\1$""").matches(usb))
            graph.graph.stream.stop()
            graph.settle()
            assertEquals(StreamState.Off, graph.graph.stream.state.value)
        }
    }

    @Test
    fun `calibration, its two actions as tall as each other also in German`() {
        val variants = Variant.entries.map { Triple(it.prefix, it.qualifiers, it.fontScale) } +
            Triple("de-font13", "de-rDE-w400dp-h860dp-port-notnight-xhdpi", 1.3f)
        for ((prefix, qualifiers, scale) in variants) {
            RuntimeEnvironment.setQualifiers(qualifiers)
            RuntimeEnvironment.setFontScale(scale)
            val c = Robolectric.buildActivity(CalibrationActivity::class.java).setup()
            graph.settle()
            val a = c.get()
            render(a, "$prefix-calibration-ready", whole = true)
            // Start and Save side by side are as tall as each other (a label on two lines made one taller).
            val start = a.findViewById<View>(R.id.primary_action)
            val save = a.findViewById<View>(R.id.save)
            assertEquals("$prefix: Start ${start.height}, Save ${save.height}", start.height, save.height)
            c.pause().stop().destroy()
        }
    }
}
