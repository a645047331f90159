package dev.motionfusion.app.sessions

import dev.motionfusion.app.platform.Sdks
import dev.motionfusion.app.offMainThread
import android.app.Activity
import androidx.appcompat.app.AlertDialog
import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.net.Uri
import android.os.Looper
import android.view.View
import android.widget.Button
import android.widget.ListView
import android.widget.TextView
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.export.ExportProvider
import dev.motionfusion.app.ui.AnglePlotView
import dev.motionfusion.app.record.CoreSessionFormat
import dev.motionfusion.app.record.Recorder
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.live.TestCapture
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.Continuation
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.sim.MotionSimulator
import dev.motionfusion.core.sim.SimulationSettings
import kotlinx.coroutines.Dispatchers
import org.junit.After
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
import org.robolectric.annotation.Config
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowDialog
import java.io.File

/** The sessions list, a session's detail with rename, delete and export, and the main screen while recording. */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class SessionsScreensTest {
    private val app = RuntimeEnvironment.getApplication()

    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        graph = TestGraph()
    }

    private fun idle() = graph.settle()

    /** A real session of [seconds] of simulated motion at 200 Hz, recorded through the capture; left unfinished if [kill]. */
    private fun record(name: String, seconds: Double, wallMs: Long, seed: Long, kill: Boolean = false, continues: Continuation? = null): File {
        val dir = offMainThread { File(File(app.filesDir, "sessions"), name) }
        val meta = SessionMetadata(appVersion = "0.1.0", startAnchor = ClockAnchor(wallMs, 1_000_000_000L), filterSettings = FilterSettings(), continues = continues)
        val c = TestCapture()
        val recorder = Recorder(CoreSessionFormat.create(dir, meta), onEnd = {}, flushIntervalNs = 50_000_000L)
        c.record(recorder)
        for (s in MotionSimulator(SimulationSettings(seed = seed, rateHz = 200.0, durationS = seconds)).run()) {
            c.offer(SessionStream.ACCELEROMETER, s.timestampNs, s.acc.x.toFloat(), s.acc.y.toFloat(), s.acc.z.toFloat())
            c.offer(SessionStream.MAGNETOMETER, s.timestampNs + 1_000, s.mag.x.toFloat(), s.mag.y.toFloat(), s.mag.z.toFloat())
            c.offer(SessionStream.GYROSCOPE, s.timestampNs + 2_000, s.gyro.x.toFloat(), s.gyro.y.toFloat(), s.gyro.z.toFloat())
            c.offer(SessionStream.GAME_ROTATION_VECTOR, s.timestampNs + 3_000, s.truth.x.toFloat(), s.truth.y.toFloat(), s.truth.z.toFloat(), s.truth.w.toFloat())
            c.nowNs = s.timestampNs
            if (c.ring.size > 256) c.drain()
        }
        c.drain()
        c.nowNs += 1_000_000_000L
        c.capture.pump() // the reorder window emptied, then flushed
        if (!kill) c.stop(recorder) // killed: flushed, then abandoned without closing
        return dir
    }

    private fun sessions(): Activity {
        val a = Robolectric.buildActivity(SessionsActivity::class.java).setup().get()
        idle()
        return a
    }

    @Test
    fun `the list shows date, duration, size, samples and rates, and repairs an interrupted session`() {
        record("session_2026-11-26_09-15-00", 30.0, 1_795_684_500_000L, 1)
        record("walk to the station", 12.0, 1_795_688_100_000L, 2)
        val killed = record("session_2026-11-26_13-05-00", 8.0, 1_795_698_300_000L, 3, kill = true)
        assertTrue(CoreSessionFormat.isInterrupted(killed))
        val a = sessions() as SessionsActivity
        assertFalse("recovered when the list opens", CoreSessionFormat.isInterrupted(killed))
        val list = a.findViewById<ListView>(R.id.sessions_list)
        assertEquals(3, list.adapter.count)
        val items = a.items
        // Newest first by the start time in meta.json: the renamed 10:15 walk sits between 13:05 and 09:15, not above them by its name.
        assertEquals(listOf("session_2026-11-26_13-05-00", "walk to the station", "session_2026-11-26_09-15-00"), items.map { it.dir.name })
        val first = items.single { it.dir.name == "session_2026-11-26_09-15-00" }.summary!!
        assertEquals(6000L, first.streams.single { it.name == "accelerometer" }.rows)
        assertEquals(200.0, first.streams.single { it.name == "gyroscope" }.rateHz, 0.5)
        assertEquals(29.995, first.durationNs / 1e9, 0.01)
        assertTrue(items.single { it.dir == killed }.summary!!.recovered)
        val row = list.adapter.getView(0, null, list)
        val line1 = row.findViewById<TextView>(R.id.session_line1).text.toString()
        assertTrue(line1, line1.contains("00:07") && line1.contains("recovered") && line1.contains("samples"))
        assertTrue(row.findViewById<TextView>(R.id.session_line2).text.contains("gyr\u00A0200\u00A0Hz"))
        Screenshots.capture(a, "sessions-list")
    }

    @Test
    fun `a recording resumed after a kill is listed as two parts, the second naming the first and the gap`() {
        val first = record("session_2026-11-26_09-15-00", 10.0, 1_795_684_500_000L, 1, kill = true)
        record(
            "session_2026-11-26_09-16-02", 6.0, 1_795_684_562_000L, 2,
            continues = Continuation(first.name, 10_995_000_000L, 52_995_000_000L),
        )
        val a = sessions() as SessionsActivity
        val list = a.findViewById<ListView>(R.id.sessions_list)
        val second = list.adapter.getView(0, null, list).findViewById<TextView>(R.id.session_line1).text.toString()
        assertTrue(second, second.endsWith(a.getString(R.string.session_continues, first.name, "00:42")))
        val earlier = list.adapter.getView(1, null, list).findViewById<TextView>(R.id.session_line1).text.toString()
        assertTrue(earlier, earlier.endsWith(a.getString(R.string.session_recovered)))
        Screenshots.capture(a, "sessions-list-resumed")
    }

    @Test
    fun `an empty list says how to record`() {
        val a = sessions()
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.sessions_empty).visibility)
        Screenshots.capture(a, "sessions-empty")
    }

    private fun detail(dir: File): SessionDetailActivity {
        val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, dir.name)
        val a = Robolectric.buildActivity(SessionDetailActivity::class.java, intent).setup().get()
        idle()
        return a
    }

    @Test
    fun `the detail shows the summary and the angle plot`() {
        val dir = record("walk to the station", 30.0, 1_795_688_100_000L, 4)
        val a = detail(dir)
        val streams = a.findViewById<TextView>(R.id.detail_streams).text.toString()
        assertTrue(streams, streams.contains("accelerometer\u00A0· 6,000\u00A0· 200.0\u00A0Hz"))
        assertTrue(streams, streams.contains("game rotation vector\u00A0· 6,000"))
        assertTrue(streams, streams.contains("Fused orientation\u00A0· 6,000 rows"))
        val plot = a.findViewById<AnglePlotView>(R.id.detail_plot)
        assertEquals(a.getString(R.string.session_plot_title), plot.contentDescription)
        Screenshots.capture(a, "session-detail")
    }

    @Test
    fun `the list says it is reading until the disk executor has read it, and keeps its items across a rotation`() {
        record("walk to the station", 4.0, 1_795_688_100_000L, 7)
        val c = Robolectric.buildActivity(SessionsActivity::class.java).setup()
        shadowOf(Looper.getMainLooper()).idle()
        val empty = c.get().findViewById<TextView>(R.id.sessions_empty)
        assertEquals(app.getString(R.string.sessions_loading), empty.text.toString())
        assertTrue("the reading waits for the disk executor", graph.disk.pending > 0)
        idle()
        assertEquals(1, c.get().items.size)
        c.recreate()
        shadowOf(Looper.getMainLooper()).idle()
        // Shown at once from the ViewModel, before the disk executor runs the refresh.
        assertEquals(1, c.get().items.size)
        assertEquals(View.GONE, c.get().findViewById<View>(R.id.sessions_empty).visibility)
    }

    @Test
    fun `the detail plots each stream's rate over time and keeps its state across a rotation`() {
        val dir = record("walk to the station", 6.0, 1_795_688_100_000L, 8)
        val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, dir.name)
        val c = Robolectric.buildActivity(SessionDetailActivity::class.java, intent).setup()
        idle()
        val rates = c.get().findViewById<dev.motionfusion.app.ui.RatePlotView>(R.id.detail_rate_plot)
        assertEquals(4, rates.laneCount) // accelerometer, gyroscope, magnetometer, game rotation vector
        assertTrue(rates.contentDescription.toString(), rates.contentDescription.contains("acc at most 200 Hz"))
        val points = c.get().findViewById<AnglePlotView>(R.id.detail_plot).pointCount
        assertTrue(points > 100)
        c.recreate()
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals("nothing read again", 0, graph.disk.pending)
        assertEquals(points, c.get().findViewById<AnglePlotView>(R.id.detail_plot).pointCount)
        assertEquals(4, c.get().findViewById<dev.motionfusion.app.ui.RatePlotView>(R.id.detail_rate_plot).laneCount)
    }

    @Test
    fun `rename checks the name and renames the folder`() {
        val dir = record("session_2026-11-26_09-15-00", 2.0, 1_795_684_500_000L, 5)
        val a = detail(dir)
        a.findViewById<Button>(R.id.detail_rename).performClick()
        assertNotNull(a.dialog)
        a.rename("../escape")
        idle()
        assertEquals(a.getString(R.string.session_rename_invalid), a.findViewById<TextView>(R.id.detail_message).text.toString())
        assertTrue(dir.exists())
        a.rename("Morning walk")
        idle()
        assertFalse(dir.exists())
        assertTrue(File(dir.parentFile, "Morning walk/meta.json").exists())
        assertEquals("Morning walk", a.findViewById<TextView>(R.id.detail_name).text.toString())
    }

    @Test
    fun `delete asks first and then removes the session`() {
        val dir = record("to delete", 2.0, 1_795_684_500_000L, 6)
        val a = detail(dir)
        a.findViewById<Button>(R.id.detail_delete).performClick()
        val dialog = ShadowDialog.getLatestDialog() as AlertDialog
        assertTrue(dialog.findViewById<TextView>(android.R.id.message)!!.text.contains("to delete"))
        dialog.getButton(AlertDialog.BUTTON_NEGATIVE).performClick()
        idle()
        assertTrue("cancel keeps it", dir.exists())
        a.findViewById<Button>(R.id.detail_delete).performClick()
        (ShadowDialog.getLatestDialog() as AlertDialog).getButton(AlertDialog.BUTTON_POSITIVE).performClick()
        idle()
        assertFalse(dir.exists())
        assertTrue(a.isFinishing)
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `share sends a content URI with a read grant that opens the session zip`() {
        val dir = record("walk", 3.0, 1_795_684_500_000L, 7)
        Robolectric.setupContentProvider(ExportProvider::class.java, ExportProvider.authority(app))
        val a = detail(dir)
        a.findViewById<Button>(R.id.detail_share).performClick()
        idle()
        val chooser = shadowOf(a).nextStartedActivity
        assertEquals(Intent.ACTION_CHOOSER, chooser.action)
        @Suppress("DEPRECATION")
        val send = chooser.getParcelableExtra<Intent>(Intent.EXTRA_INTENT)!!
        assertEquals(Intent.ACTION_SEND, send.action)
        assertEquals("application/zip", send.type)
        assertTrue(send.flags and Intent.FLAG_GRANT_READ_URI_PERMISSION != 0)
        @Suppress("DEPRECATION")
        val uri = send.getParcelableExtra<Uri>(Intent.EXTRA_STREAM)!!
        assertEquals("content", uri.scheme)
        assertEquals(ExportProvider.authority(app), uri.authority)
        val copy = offMainThread { File(app.cacheDir, "received.zip") }
        app.contentResolver.openInputStream(uri)!!.use { input -> copy.outputStream().use { input.copyTo(it) } }
        SessionReader.open(copy.toPath()).use { r ->
            assertEquals(600L, r.metadata.streams.getValue(SessionStream.GYROSCOPE).samples)
            assertTrue(SessionStream.ORIENTATION in r.streams)
        }
        // Read-only, and nothing outside the export folder.
        assertTrue(runCatching { app.contentResolver.openOutputStream(uri) }.isFailure)
        val outside = Uri.parse("content://${ExportProvider.authority(app)}/..%2Ffiles%2Fsessions%2Fwalk%2Fmeta.json")
        assertTrue(runCatching { app.contentResolver.openInputStream(outside) }.isFailure)
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `the detail offers Save to Downloads from API 29 and Save as on every version`() {
        val a = detail(record("walk", 3.0, 1_795_684_500_000L, 9))
        val expected = if (android.os.Build.VERSION.SDK_INT >= 29) View.VISIBLE else View.GONE
        assertEquals(expected, a.findViewById<Button>(R.id.detail_downloads).visibility)
        assertEquals(View.VISIBLE, a.findViewById<Button>(R.id.detail_save_as).visibility)
        assertEquals(View.VISIBLE, a.findViewById<Button>(R.id.detail_share).visibility)
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `save as writes the zip into the document the user picked`() {
        val dir = record("walk", 3.0, 1_795_684_500_000L, 8)
        val a = detail(dir)
        a.findViewById<Button>(R.id.detail_save_as).performClick()
        val create = shadowOf(a).nextStartedActivityForResult
        assertEquals(Intent.ACTION_CREATE_DOCUMENT, create.intent.action)
        assertEquals("application/zip", create.intent.type)
        assertEquals("walk.zip", create.intent.getStringExtra(Intent.EXTRA_TITLE))
        val picked = offMainThread { File(app.cacheDir, "picked/walk.zip").apply { parentFile!!.mkdirs(); createNewFile() } }
        shadowOf(a).receiveResult(create.intent, Activity.RESULT_OK, Intent().setData(Uri.fromFile(picked)))
        idle()
        assertEquals(a.getString(R.string.export_done_document), a.findViewById<TextView>(R.id.detail_message).text.toString())
        SessionReader.open(picked.toPath()).use { r -> assertEquals(600L, r.metadata.streams.getValue(SessionStream.ACCELEROMETER).samples) }
    }

    @Test
    fun `the main screen while recording`() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        val sensors = SensorStreams.all.associateWith { s ->
            SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.key}").build().also(sm::addSensor)
        }
        graph = TestGraph() // after the sensors: the capture sees them
        val service = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction("dev.motionfusion.app.record.START"))
            .create().startCommand(0, 1)
        val main = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        graph.settle()
        for (i in 0 until 500) {
            val t = 1_000_000_000L + i * 5_000_000L
            fun send(s: SessionStream, vararg v: Float) = sm.sendSensorEventToListeners(
                SensorEventBuilder.newBuilder().setSensor(sensors.getValue(s)).setValues(v).setTimestamp(t).setAccuracy(3).build(),
            )
            send(SessionStream.ACCELEROMETER, 0f, 0f, 9.81f)
            send(SessionStream.GYROSCOPE, 0f, 0f, 0f)
            send(SessionStream.MAGNETOMETER, 0f, 22f, -40f)
        }
        graph.pump()
        val active = graph.graph.recordings.state.value as RecordingState.Active
        assertEquals(1500L, active.rows())
        shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(1))
        val toggle = main.findViewById<Button>(R.id.record_toggle)
        assertEquals(main.getString(R.string.record_stop), toggle.text.toString())
        val status = main.findViewById<TextView>(R.id.record_status).text.toString()
        assertTrue(status, status.contains("1,500 samples"))
        Screenshots.capture(main, "main-recording")
        assertEquals(View.GONE, main.findViewById<View>(R.id.record_after).visibility)
        // Stop asks first.
        toggle.performClick()
        val ask = org.robolectric.shadows.ShadowDialog.getLatestDialog() as androidx.appcompat.app.AlertDialog
        assertEquals(main.getString(R.string.record_stop_confirm_text), ask.findViewById<TextView>(android.R.id.message)!!.text.toString())
        assertNull("nothing stopped before the answer", shadowOf(app).peekNextStartedService())
        shadowOf(Looper.getMainLooper()).idle()
        Screenshots.captureDialog(main, ask, "main-recording-stop-confirm")
        ask.getButton(androidx.appcompat.app.AlertDialog.BUTTON_POSITIVE).performClick()
        shadowOf(Looper.getMainLooper()).idle()
        val stop = shadowOf(app).nextStartedService
        assertEquals("dev.motionfusion.app.record.STOP", stop.action)
        service.get().onStartCommand(stop, 0, 2)
        graph.settle()
        val ended = graph.graph.recordings.state.value as RecordingState.Ended
        shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(1))
        assertEquals(main.getString(R.string.record_start), toggle.text.toString())
        // The session just saved: Open and Share right there.
        assertEquals(View.VISIBLE, main.findViewById<View>(R.id.record_after).visibility)
        Screenshots.capture(main, "main-recording-saved")
        main.findViewById<Button>(R.id.record_open).performClick()
        val open = shadowOf(main).nextStartedActivity
        assertEquals(SessionDetailActivity::class.java.name, open.component!!.className)
        assertEquals(ended.session!!.name, open.getStringExtra(SessionDetailActivity.EXTRA_SESSION))
        assertFalse(open.getBooleanExtra(SessionDetailActivity.EXTRA_SHARE, true))
        main.findViewById<Button>(R.id.record_share).performClick()
        val share = shadowOf(main).nextStartedActivity
        assertEquals(ended.session!!.name, share.getStringExtra(SessionDetailActivity.EXTRA_SESSION))
        assertTrue(share.getBooleanExtra(SessionDetailActivity.EXTRA_SHARE, false))
        // The detail opened for Share starts the share at once: the chooser with the session's zip.
        Robolectric.setupContentProvider(ExportProvider::class.java, ExportProvider.authority(app))
        val detail = Robolectric.buildActivity(SessionDetailActivity::class.java, share).setup().get()
        graph.settle()
        val chooser = shadowOf(detail).nextStartedActivity
        assertEquals(Intent.ACTION_CHOOSER, chooser.action)
    }
}
