package dev.motionfusion.app

import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.widget.TextView
import android.widget.CompoundButton
import com.google.android.material.slider.Slider
import androidx.core.graphics.ColorUtils
import com.google.android.material.R as MaterialR
import com.google.android.material.color.MaterialColors
import dev.motionfusion.app.fusion.EffectiveMode
import dev.motionfusion.app.fusion.FusionMode
import dev.motionfusion.app.fusion.FusionState
import dev.motionfusion.app.live.LiveScreen
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.fusion.ModeReason
import dev.motionfusion.app.fusion.SensorStats
import dev.motionfusion.app.sensor.SensorKind
import dev.motionfusion.app.sessions.AngleSeries
import dev.motionfusion.app.sessions.RateSeries
import dev.motionfusion.app.sessions.SessionDetailUiState
import dev.motionfusion.app.sessions.SessionItem
import dev.motionfusion.app.sessions.SessionsUiState
import dev.motionfusion.app.sessions.SessionDetailActivity
import dev.motionfusion.app.sessions.SessionSummary
import dev.motionfusion.app.sessions.SessionsActivity
import dev.motionfusion.app.sessions.StreamSummary
import dev.motionfusion.app.settings.SettingsActivity
import dev.motionfusion.app.ui.AnglePlotView
import dev.motionfusion.app.ui.PlotMarker
import dev.motionfusion.app.ui.RatePlotView
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.Quaternion
import dev.motionfusion.core.Vector3
import dev.motionfusion.core.session.Marker
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
import kotlin.math.sin

/**
 * Every screen rendered to PNG (target/screenshots) in its states, on a phone held upright and
 * sideways and on a tablet, light and dark, with checks on the layout (texts inside the screen,
 * not cut short, not overlapping) and the plot's colours. The states are made by hand and bound
 * through the screens' own rendering ([LiveScreen.show], `SessionsActivity.show`,
 * `SessionDetailActivity.show`), so they do not depend on where the app gets them.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class ScreensTest {
    private val app = RuntimeEnvironment.getApplication()

    /** A screen shape: Robolectric qualifiers (before and after the night one) and the file name's part. */
    private enum class Shape(val size: String, val density: String) {
        PHONE("w400dp-h860dp-port", "xhdpi"),
        LANDSCAPE("w860dp-h400dp-land", "xhdpi"),
        TABLET("sw800dp-w800dp-h1280dp-port", "hdpi"),
        TABLET_LANDSCAPE("sw800dp-w1280dp-h800dp-land", "hdpi"),
    }

    private fun configure(shape: Shape, dark: Boolean) {
        RuntimeEnvironment.setQualifiers("${shape.size}-${if (dark) "night" else "notnight"}-${shape.density}")
    }

    private fun name(screen: String, shape: Shape, dark: Boolean) = "$screen-${shape.name.lowercase().replace('_', '-')}-${if (dark) "dark" else "light"}"

    @Before
    fun setUp() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        for ((type, name) in listOf(
            Sensor.TYPE_ACCELEROMETER to "BMI260 Accelerometer",
            Sensor.TYPE_GYROSCOPE to "BMI260 Gyroscope",
            Sensor.TYPE_MAGNETIC_FIELD to "AK09918 Magnetometer",
            Sensor.TYPE_ROTATION_VECTOR to "Rotation Vector",
        )) sm.addSensor(SensorBuilder.newBuilder().setType(type).setName(name).build())
        graph = TestGraph() // after the sensors: the capture sees them
    }

    private lateinit var graph: TestGraph

    private fun idle() = graph.settle()

    /** The sessions folder (created off the main thread, as the app does). */
    private fun sessionsRoot(): File {
        var root: File? = null
        Thread { root = graph.graph.sessions.root() }.apply { start(); join() }
        return root!!
    }

    // ---- The live screen ----

    private fun state(
        tNs: Long, q: Quaternion?, rv: Quaternion?,
        mode: EffectiveMode = EffectiveMode(FusionMode.MARG, ModeReason.AS_CHOSEN),
        magAccuracy: Int = SensorManager.SENSOR_STATUS_ACCURACY_HIGH, fieldUt: Double? = 47.3, disturbed: Boolean = false,
    ) = LiveStates.state(tNs, q, rv, mode, magAccuracy, fieldUt, disturbed)

    /** The live screen after 12 s of swaying at 60 frames/s, the rotation vector 3° off in heading. */
    private fun live(
        shape: Shape,
        dark: Boolean,
        markers: List<PlotMarker> = emptyList(),
        last: (Long, Quaternion, Quaternion?) -> FusionState = { t, q, rv -> state(t, q, rv) },
        ghost: Boolean = true,
    ): MainActivity {
        configure(shape, dark)
        val a = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        idle()
        LiveStates.sway(LiveScreen(a, graph.capture.sensorInfo), markers, ghost, last)
        return a
    }

    private fun assertPlotReadable(a: android.app.Activity, plotId: Int, name: String) {
        val plot = a.findViewById<AnglePlotView>(plotId)
        val card = MaterialColors.getColor(plot, MaterialR.attr.colorSurfaceContainerHighest)
        val colours = (0..2).map { plot.colour(it) }
        assertEquals("$name: three plot colours", 3, colours.toSet().size)
        for (c in colours) {
            val contrast = ColorUtils.calculateContrast(c, card or 0xFF000000.toInt())
            assertTrue("$name: plot colour ${Integer.toHexString(c)} on ${Integer.toHexString(card)}: contrast $contrast", contrast >= 3.0)
        }
    }

    @Test
    fun `live screen waiting for sensors`() {
        for (dark in listOf(false, true)) {
            configure(Shape.PHONE, dark)
            val a = Robolectric.buildActivity(MainActivity::class.java).setup().get()
            idle()
            Screenshots.captureScreen(a, name("live-waiting", Shape.PHONE, dark))
        }
    }

    @Test
    fun `live screen moving, in every shape, light and dark`() {
        for (shape in Shape.entries) for (dark in listOf(false, true)) {
            val a = live(shape, dark)
            val n = name("live-moving", shape, dark)
            Screenshots.captureScreen(a, n)
            assertPlotReadable(a, R.id.plot, n)
            // The model, the instruments and the plot are on the screen the user sees first, at a usable size.
            val screenH = a.window.decorView.height
            for (id in listOf(R.id.phone_model, R.id.attitude, R.id.compass)) {
                val v = a.findViewById<View>(id)
                val at = IntArray(2).also(v::getLocationInWindow)
                assertTrue("$n: ${a.resources.getResourceEntryName(id)} below the fold at ${at[1]}", at[1] + v.height / 2 < screenH)
                assertTrue("$n: ${a.resources.getResourceEntryName(id)} ${v.width}×${v.height}", v.width >= 100 && v.height >= 100)
            }
            if (shape == Shape.TABLET || shape == Shape.TABLET_LANDSCAPE) {
                // A tablet's model card is not a tall empty frame around a model drawn to the column's width.
                val model = a.findViewById<View>(R.id.phone_model)
                assertTrue("$n: model ${model.width}×${model.height}", model.height <= 1.2 * model.width)
            }
        }
    }

    @Test
    fun `live screen with magnetic warnings`() {
        for (dark in listOf(false, true)) {
            val a = live(Shape.PHONE, dark, last = { t, q, rv ->
                state(t, q, rv, magAccuracy = SensorManager.SENSOR_STATUS_ACCURACY_LOW, fieldUt = 88.6, disturbed = true)
            })
            assertEquals(View.VISIBLE, a.findViewById<View>(R.id.mag_warning).visibility)
            // Scrolled to the warning, as a user reading it would.
            val warning = a.findViewById<View>(R.id.mag_warning)
            Screenshots.captureScreen(a, name("live-mag-warning", Shape.PHONE, dark))
            warning.requestRectangleOnScreen(android.graphics.Rect(0, 0, warning.width, warning.height), true)
            Screenshots.captureScreen(a, name("live-mag-warning-scrolled", Shape.PHONE, dark))
        }
    }

    @Test
    fun `live screen without magnetometer`() {
        val a = live(Shape.PHONE, false, ghost = false, last = { t, q, _ ->
            state(t, q, null, mode = EffectiveMode(FusionMode.IMU, ModeReason.NO_MAGNETOMETER))
        })
        Screenshots.captureScreen(a, name("live-no-magnetometer", Shape.PHONE, false))
    }

    /** A recording of [streams] streams that started [elapsedS] ago, with [markers] set. */
    private fun recording(elapsedS: Long, markers: List<PlotMarker> = emptyList(), streams: Int = 4) = RecordingState.Active(
        File(sessionsRoot(), "session_2026-12-01_18-40-00"), graph.clock.elapsedNs / 1_000_000 - elapsedS * 1000, rows = { 41_522L },
        markers = { markers.map { Marker(it.timestampNs, it.text) } }, streams = streams,
    )

    /** Vertical lines of [colour] across most of [plot]'s height in [b]: the markers drawn. */
    private fun markerLines(b: android.graphics.Bitmap, plot: View, colour: Int): Int {
        val r = Screenshots.boundsInWindow(plot)
        var lines = 0
        var inLine = false
        for (x in r.left until r.right) {
            val column = android.graphics.Rect(x, r.top + r.height() / 4, x + 1, r.bottom - r.height() / 4)
            val on = Screenshots.share(b, column, colour, tolerance = 40) > 0.6
            if (on && !inLine) lines++
            inLine = on
        }
        return lines
    }

    @Test
    fun `live screen while recording, with markers`() {
        val markers = listOf(PlotMarker(1_000_000_000L + 4_200_000_000L, "start walk"), PlotMarker(1_000_000_000L + 9_600_000_000L, "stairs"))
        for (shape in listOf(Shape.PHONE, Shape.LANDSCAPE, Shape.TABLET)) for (dark in listOf(false, true)) {
            // Record with a start delay first: the countdown on the record bar, its button cancelling it.
            graph.graph.recordings.set(RecordingState.Idle)
            val before = live(shape, dark, markers)
            graph.graph.recordings.countdown.start(3) {}
            shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(600))
            assertEquals("Cancel (3)", before.findViewById<TextView>(R.id.record_toggle).text.toString())
            Screenshots.captureScreen(before, name("live-countdown", shape, dark))
            graph.graph.recordings.countdown.cancel()
            graph.graph.recordings.set(recording(83, markers))
            val a = live(shape, dark, markers)
            shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(1))
            val n = name("live-recording", shape, dark)
            Screenshots.captureScreen(a, n)
            val mark = a.findViewById<View>(R.id.record_mark)
            assertEquals("$n: the Mark button", View.VISIBLE, mark.visibility)
            assertEquals(a.getString(R.string.record_stop), a.findViewById<TextView>(R.id.record_toggle).text.toString())
            val status = a.findViewById<TextView>(R.id.record_status).text.toString()
            assertTrue("$n: $status", status.startsWith("Recording 01:23 · 41,522 samples · 2 markers"))
            // Scrolled to the plot's card, where the markers are: two labelled lines in the picture.
            val plot = a.findViewById<AnglePlotView>(R.id.plot)
            val card = plot.parent.parent as View
            card.requestRectangleOnScreen(android.graphics.Rect(0, 0, card.width, card.height), true)
            val b = Screenshots.captureScreen(a, name("live-recording-plot", shape, dark))
            assertEquals("$n: marker lines in the plot", 2, markerLines(b, plot, MaterialColors.getColor(plot, MaterialR.attr.colorTertiary)))
        }
    }

    @Test
    fun `the notification explained before the first recording`() {
        for ((shape, dark) in listOf(Shape.PHONE to false, Shape.PHONE to true, Shape.LANDSCAPE to false, Shape.TABLET to true)) {
            val a = live(shape, dark) // the explanation never answered
            a.findViewById<View>(R.id.record_toggle).performClick()
            val dialog = org.robolectric.shadows.ShadowDialog.getLatestDialog() as androidx.appcompat.app.AlertDialog
            assertTrue(dialog.isShowing)
            idle()
            val n = name("notification-explained", shape, dark)
            val (b, at) = Screenshots.captureDialog(a, dialog, n)
            // The dialog's card is drawn: its surface fills most of the dialog's window, its texts are on it.
            val surface = MaterialColors.getColor(dialog.window!!.decorView, MaterialR.attr.colorSurfaceContainerHigh)
            assertTrue("$n: the dialog's surface ${Screenshots.share(b, at, surface)}", Screenshots.share(b, at, surface, tolerance = 4) > 0.5)
            for (id in listOf(androidx.appcompat.R.id.alertTitle, android.R.id.message, android.R.id.button1, android.R.id.button2)) {
                val v = dialog.findViewById<TextView>(id)!!
                val r = Screenshots.boundsInWindow(v) // the dialog's window laid out where it is drawn
                assertTrue("$n: ${v.text.take(20)} at $r inside the dialog $at", at.contains(r) && r.height() > 0)
                assertTrue("$n: ${v.text.take(20)} drawn", Screenshots.colours(b, r) > 3)
            }
            assertEquals(a.getString(R.string.record_notifications_continue), dialog.getButton(androidx.appcompat.app.AlertDialog.BUTTON_POSITIVE).text.toString())
            // Held upright, the whole text is shown without scrolling; sideways it scrolls between the title and the buttons.
            val scroll = dialog.findViewById<View>(androidx.appcompat.R.id.scrollView)!!
            val text = dialog.findViewById<TextView>(android.R.id.message)!!
            if (shape != Shape.LANDSCAPE) assertTrue("$n: the message fits", scroll.height >= text.height)
            dialog.dismiss()
        }
    }

    @Test
    fun `the other screens while recording show it under their app bar`() {
        val root = sessionsRoot()
        for ((shape, dark) in listOf(Shape.PHONE to false, Shape.PHONE to true, Shape.LANDSCAPE to true, Shape.TABLET to false)) {
            configure(shape, dark)
            graph.graph.recordings.set(recording(133))
            val screens = listOf(
                "settings-recording" to Robolectric.buildActivity(SettingsActivity::class.java).setup().get(),
                "sessions-recording" to Robolectric.buildActivity(SessionsActivity::class.java).setup().get().also {
                    idle()
                    it.show(SessionsUiState.Loaded(listOf(SessionItem(File(root, "session_2026-12-01_18-40-00"), summary("session_2026-12-01_18-40-00", 133, 200.0, 1_795_698_300_000L), null, recordingNow = true)) + sessionItems(root)))
                },
                "session-detail-recording" to detailScreen().also { it.show(detailState()) },
                "calibration-recording" to Robolectric.buildActivity(dev.motionfusion.app.calibration.CalibrationActivity::class.java).setup().get(),
            )
            for ((screen, a) in screens) {
                idle()
                val n = name(screen, shape, dark)
                val b = Screenshots.captureScreen(a, n)
                val banner = a.findViewById<View>(R.id.recording_banner)
                assertEquals(n, View.VISIBLE, banner.visibility)
                assertEquals(n, "Recording 02:13 · 4 streams", a.findViewById<TextView>(R.id.recording_banner_text).text.toString())
                val r = Screenshots.boundsInWindow(banner)
                assertEquals("$n: under the app bar", Screenshots.boundsInWindow(a.findViewById(R.id.toolbar)).bottom, r.top)
                val fill = MaterialColors.getColor(banner, MaterialR.attr.colorErrorContainer)
                assertTrue("$n: the banner's colour in the picture", Screenshots.share(b, r, fill, tolerance = 2) > 0.6)
                val text = MaterialColors.getColor(banner, MaterialR.attr.colorOnErrorContainer)
                assertTrue("$n: the banner's text readable", ColorUtils.calculateContrast(text, fill) >= 4.5)
            }
        }
    }

    // ---- Settings ----

    @Test
    fun `settings screen`() {
        for ((shape, dark) in listOf(Shape.PHONE to false, Shape.PHONE to true, Shape.LANDSCAPE to false, Shape.LANDSCAPE to true, Shape.TABLET to true)) {
            configure(shape, dark)
            val a = Robolectric.buildActivity(SettingsActivity::class.java).setup().get()
            idle()
            val png = name("settings", shape, dark)
            // Recording first; the filter's tuning folded under Advanced.
            Screenshots.captureScreen(a, png)
            Screenshots.captureWhole(a, "$png-folded-all")
            assertTrue(a.row("beta").isShown.not())
            a.findViewById<View>(R.id.settings_advanced_toggle).performClick()
            idle()
            // The whole form, every section, as tall as it is.
            val full = Screenshots.captureWhole(a, "$png-all")
            assertTrue("$png: the whole form is taller than the screen", full.height > a.resources.configuration.screenHeightDp * a.resources.displayMetrics.density)
            assertTrue(a.getString(R.string.settings_section_rejection) in texts(a))
            assertEquals(FilterSettings().beta.toFloat(), a.row("beta").findViewById<Slider>(R.id.setting_slider).value, 0f)
        }
        // Changed, applied at once, with Undo offered; a 0 = off setting switched off.
        configure(Shape.PHONE, false)
        val a = Robolectric.buildActivity(SettingsActivity::class.java).setup().get()
        a.findViewById<View>(R.id.settings_advanced_toggle).performClick()
        a.row("beta").findViewById<Slider>(R.id.setting_slider).value = 0.12f
        a.row("heading_gain_1_s").findViewById<CompoundButton>(R.id.setting_switch).isChecked = false
        idle()
        assertEquals("", a.findViewById<TextView>(R.id.settings_message).text.toString())
        assertTrue(a.snackbar!!.isShown)
        assertEquals("off", a.row("heading_gain_1_s").findViewById<TextView>(R.id.setting_value).text.toString())
        assertEquals("0.12 rad/s (6.9°/s)", a.row("beta").findViewById<TextView>(R.id.setting_value).text.toString())
        Screenshots.captureScreen(a, "settings-changed-phone-light")
    }

    /** Every text of [a]'s window. */
    private fun texts(a: android.app.Activity): List<String> {
        val out = ArrayList<String>()
        fun walk(v: View) {
            if (v is TextView) out += v.text.toString()
            if (v is android.view.ViewGroup) for (i in 0 until v.childCount) walk(v.getChildAt(i))
        }
        walk(a.window.decorView)
        return out
    }

    // ---- Sessions ----

    private fun summary(name: String, seconds: Long, hz: Double, wallMs: Long) = SessionStates.summary(name, seconds, hz, wallMs)

    private fun sessionItems(root: File) = SessionStates.items(root)

    @Test
    fun `sessions list, empty and full`() {
        for (dark in listOf(false, true)) {
            configure(Shape.PHONE, dark)
            val empty = Robolectric.buildActivity(SessionsActivity::class.java).setup().get()
            idle()
            assertEquals(View.VISIBLE, empty.findViewById<View>(R.id.sessions_empty).visibility)
            Screenshots.captureScreen(empty, name("sessions-empty", Shape.PHONE, dark))
        }
        val items = sessionItems(sessionsRoot())
        for ((shape, dark) in listOf(Shape.PHONE to false, Shape.PHONE to true, Shape.TABLET to false, Shape.LANDSCAPE to true)) {
            configure(shape, dark)
            val a = Robolectric.buildActivity(SessionsActivity::class.java).setup().get()
            idle()
            a.show(SessionsUiState.Loaded(items))
            Screenshots.captureScreen(a, name("sessions-list", shape, dark))
            assertEquals(View.GONE, a.findViewById<View>(R.id.sessions_empty).visibility)
        }
    }

    private val detailName = "walk to the station"

    /** The detail screen of [detailName] (its folder exists), showing what it read. */
    private fun detailScreen(): SessionDetailActivity {
        val dir = File(sessionsRoot(), detailName)
        Thread { dir.mkdirs() }.apply { start(); join() } // off the main thread, as the app's disk work
        val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, detailName)
        val a = Robolectric.buildActivity(SessionDetailActivity::class.java, intent).setup().get()
        idle()
        return a
    }

    private fun detailState() = SessionStates.detail(detailName)

    @Test
    fun `session detail with angles, markers and rates`() {
        for ((shape, dark) in listOf(Shape.PHONE to false, Shape.PHONE to true, Shape.LANDSCAPE to false, Shape.TABLET to true)) {
            configure(shape, dark)
            val a = detailScreen()
            a.show(detailState())
            val png = name("session-detail", shape, dark)
            Screenshots.captureScreen(a, png)
            assertPlotReadable(a, R.id.detail_plot, png)
            assertEquals(4, a.findViewById<RatePlotView>(R.id.detail_rate_plot).laneCount)
            assertTrue(a.findViewById<RatePlotView>(R.id.detail_rate_plot).contentDescription.contains("mag at most 100 Hz"))
        }
    }
}
