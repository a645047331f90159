package dev.motionfusion.app

import android.app.Activity
import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.widget.TextView
import androidx.appcompat.widget.Toolbar
import dev.motionfusion.app.calibration.CalibrationActivity
import dev.motionfusion.app.record.RecordingBanner
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.sessions.SessionDetailActivity
import dev.motionfusion.app.sessions.SessionsActivity
import dev.motionfusion.app.settings.SettingsActivity
import org.junit.Assert.assertEquals
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.android.controller.ActivityController
import org.robolectric.shadows.SensorBuilder
import java.io.File
import java.time.Duration

/**
 * The recording seen from every screen but the live one: the banner under the app bar appears
 * when a recording starts, counts the elapsed time on the injected clock, says how many streams
 * are recorded, goes back to the live screen on a tap, stops the recording from its Stop, and is
 * gone when the recording ends; all from the one [dev.motionfusion.app.record.Recordings] state.
 */
@RunWith(RobolectricTestRunner::class)
class RecordingBannerTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        for (type in listOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE, Sensor.TYPE_MAGNETIC_FIELD)) {
            sm.addSensor(SensorBuilder.newBuilder().setType(type).setName("Test $type").build())
        }
        graph = TestGraph()
    }

    private val screens: List<Pair<String, () -> ActivityController<out Activity>>> = listOf(
        "settings" to { Robolectric.buildActivity(SettingsActivity::class.java) },
        "sessions" to { Robolectric.buildActivity(SessionsActivity::class.java) },
        "session detail" to {
            Robolectric.buildActivity(
                SessionDetailActivity::class.java,
                Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, "walk"),
            )
        },
        "calibration" to { Robolectric.buildActivity(CalibrationActivity::class.java) },
    )

    private fun banner(a: Activity): View = a.findViewById(R.id.recording_banner)
    private fun bannerText(a: Activity) = a.findViewById<TextView>(R.id.recording_banner_text).text.toString()
    private fun nowMs() = graph.clock.elapsedNs / 1_000_000
    private fun tick(seconds: Long) {
        graph.clock.elapsedNs += seconds * 1_000_000_000L
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(seconds))
    }

    private fun active(startedMs: Long, streams: Int = 4, still: Boolean = false) =
        RecordingState.Active(File("sessions", "session_now"), startedMs, rows = { 41_522L }, still = still, streams = streams)

    @Test
    fun `every screen shows the recording under its app bar while it runs, and only then`() {
        for ((name, build) in screens) {
            graph.graph.recordings.set(RecordingState.Idle)
            val c = build().setup()
            val a = c.get()
            graph.settle()
            assertEquals("$name, idle", View.GONE, banner(a).visibility)

            graph.graph.recordings.set(RecordingState.Preparing(0, 0))
            shadowOf(Looper.getMainLooper()).idle()
            assertEquals("$name, starting", View.VISIBLE, banner(a).visibility)
            assertEquals(a.getString(R.string.record_preparing), bannerText(a))
            graph.graph.recordings.set(RecordingState.Preparing(1, 3))
            shadowOf(Looper.getMainLooper()).idle()
            assertEquals("Repairing interrupted sessions before recording: 1 of 3 done", bannerText(a))

            graph.graph.recordings.set(active(nowMs() - 133_000))
            shadowOf(Looper.getMainLooper()).idle()
            assertEquals("$name, recording", View.VISIBLE, banner(a).visibility)
            assertEquals("Recording 02:13 · 4 streams", bannerText(a))
            tick(5)
            assertEquals("$name: the elapsed time counts on", "Recording 02:18 · 4 streams", bannerText(a))
            // Right under the app bar, across the screen.
            val toolbar = a.findViewById<Toolbar>(R.id.toolbar)
            assertEquals("$name: below the app bar", toolbar.bottom, banner(a).top)
            assertEquals(toolbar.parent, banner(a).parent)
            assertEquals(toolbar.width, banner(a).width)

            graph.graph.recordings.set(RecordingState.NotStarted(dev.motionfusion.app.platform.Foreground.Refusal.BACKGROUND))
            shadowOf(Looper.getMainLooper()).idle()
            assertEquals("$name, not started", View.GONE, banner(a).visibility)
            graph.graph.recordings.set(active(nowMs() - 1_000, streams = 1))
            shadowOf(Looper.getMainLooper()).idle()
            assertEquals("Recording 00:01 · 1 stream", bannerText(a))
            graph.graph.recordings.set(RecordingState.Idle)
            shadowOf(Looper.getMainLooper()).idle()
            assertEquals("$name, ended", View.GONE, banner(a).visibility)
            c.pause().stop().destroy()
        }
    }

    @Test
    fun `a tap goes back to the live screen, Stop stops the recording`() {
        graph.graph.recordings.set(active(nowMs() - 10_000))
        for ((name, build) in screens) {
            val c = build().setup()
            val a = c.get()
            graph.settle()
            banner(a).performClick()
            val back = shadowOf(a).nextStartedActivity
            assertEquals(name, MainActivity::class.java.name, back.component!!.className)
            assertTrue("$name: the live screen brought back, not stacked", back.flags and Intent.FLAG_ACTIVITY_CLEAR_TOP != 0)
            a.findViewById<View>(R.id.recording_banner_stop).performClick()
            // Asked first: nothing stopped until the user confirms.
            assertNull("$name: stopped without asking", shadowOf(app).peekNextStartedService())
            val ask = a.findViewById<RecordingBanner>(R.id.recording_banner).dialog!!
            assertEquals(app.getString(R.string.record_stop_confirm_title), ask.findViewById<TextView>(androidx.appcompat.R.id.alertTitle)!!.text.toString())
            ask.getButton(androidx.appcompat.app.AlertDialog.BUTTON_NEGATIVE).performClick()
            shadowOf(Looper.getMainLooper()).idle()
            assertNull("$name: Keep recording stops nothing", shadowOf(app).peekNextStartedService())
            a.findViewById<View>(R.id.recording_banner_stop).performClick()
            a.findViewById<RecordingBanner>(R.id.recording_banner).dialog!!.getButton(androidx.appcompat.app.AlertDialog.BUTTON_POSITIVE).performClick()
            shadowOf(Looper.getMainLooper()).idle()
            val stop = shadowOf(app).nextStartedService
            assertEquals(name, RecordingService::class.java.name, stop.component!!.className)
            assertEquals(name, RecordingService.ACTION_STOP, stop.action)
            c.pause().stop().destroy()
        }
    }

    @Test
    fun `a still recording says so, and a stopped screen does not watch the state`() {
        val c = Robolectric.buildActivity(CalibrationActivity::class.java).setup()
        graph.settle()
        graph.graph.recordings.set(active(nowMs() - 65_000, streams = 2, still = true))
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals("Still recording 01:05 · 2 streams", bannerText(c.get()))
        c.pause().stop()
        graph.graph.recordings.set(RecordingState.Idle)
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals("not refreshed while stopped", View.VISIBLE, banner(c.get()).visibility)
        c.start().resume()
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals("refreshed when started again", View.GONE, banner(c.get()).visibility)
        c.pause().stop().destroy()
    }

    @Test
    fun `the live screen shows the recording in its record bar, not in a banner`() {
        val a = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        graph.graph.recordings.set(active(nowMs() - 10_000))
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertNull(a.findViewById<View>(R.id.recording_banner))
        assertTrue(a.findViewById<TextView>(R.id.record_status).text.startsWith("Recording 00:1"))
    }
}
