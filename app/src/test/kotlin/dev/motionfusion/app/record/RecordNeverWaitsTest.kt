package dev.motionfusion.app.record

import android.content.Intent
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.widget.TextView
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.export.Exporter
import dev.motionfusion.app.offMainThread
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.app.sessions.SessionDetailActivity
import dev.motionfusion.app.sessions.SessionDetailViewModel
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionWriter
import kotlinx.coroutines.CancellationException
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
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
import androidx.lifecycle.ViewModelProvider
import com.google.android.material.progressindicator.LinearProgressIndicator
import java.io.File
import java.util.concurrent.CountDownLatch

/**
 * A recording's start never waits behind the screens' disk work: with a share of a whole session
 * held in the screens' queue (it never runs until the test lets it), Record goes from the press to
 * recording on the recording's own queue. Exports show their progress and can be cancelled, leaving
 * nothing behind.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class RecordNeverWaitsTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph
    private val name = "walk home"

    @Before
    fun setUp() {
        val sensors = shadowOf(app.getSystemService(SensorManager::class.java))
        SensorStreams.all.forEach { s -> sensors.addSensor(SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}").build()) }
        graph = TestGraph()
        // A finished session of 200,000 accelerometer rows (several MB: the zip takes a while on a phone).
        offMainThread {
            val dir = File(app.filesDir, "sessions/$name")
            val w = SessionWriter.create(dir.toPath(), SessionMetadata(startAnchor = ClockAnchor(1_764_165_792_123L, 1_000_000_000L)))
            for (i in 0 until 200_000) w.accelerometer(1_000_000_000L + i * 5_000_000L, 0.1f * (i % 7), 0.2f, 9.81f, 3)
            w.close()
        }
    }

    private fun idle() = shadowOf(Looper.getMainLooper()).idle()

    private fun exportsLeft(): List<String> = offMainThread { File(app.cacheDir, "exports").list()?.toList() ?: emptyList() }

    @Test
    fun `Record does not wait for a share in progress, and the share is cancelled without leaving a zip`() {
        val detail = Robolectric.buildActivity(SessionDetailActivity::class.java, Intent(app, SessionDetailActivity::class.java).putExtra("dev.motionfusion.app.sessions.SESSION", name)).setup()
        graph.settle()
        val a = detail.get()
        a.findViewById<View>(R.id.detail_share).performClick()
        idle()
        // The share waits in the screens' queue, shown with its progress and Cancel.
        assertEquals(1, graph.disk.pending)
        assertEquals(View.VISIBLE, a.findViewById<View>(R.id.detail_export_row).visibility)
        assertEquals(app.getString(R.string.export_progress, 0), a.findViewById<TextView>(R.id.detail_export_text).text.toString())
        assertFalse(a.findViewById<View>(R.id.detail_share).isEnabled)
        Screenshots.assertLaidOut(a, "detail-exporting")
        Screenshots.captureWhole(a, "detail-exporting")

        // Record: only the recording's queue and the main thread run; the share stays held.
        val pressedNs = graph.clock.elapsedNs
        val c = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START))
            .create().startCommand(0, 1)
        var rounds = 0
        while (graph.graph.recordings.state.value !is RecordingState.Active && rounds++ < 20) {
            idle()
            graph.recordingDisk.runAll()
            graph.capture.pump()
            idle()
        }
        assertTrue("recording: ${graph.graph.recordings.state.value}", graph.graph.recordings.state.value is RecordingState.Active)
        assertEquals("the share is still waiting", 1, graph.disk.pending)
        assertEquals("no time passed on the injected clock between the press and recording", pressedNs, graph.clock.elapsedNs)
        idle()
        Screenshots.assertLaidOut(a, "detail-exporting-while-recording")
        Screenshots.captureWhole(a, "detail-exporting-while-recording")

        // Cancel: the held share never writes its zip.
        a.findViewById<View>(R.id.detail_export_cancel).performClick()
        idle()
        graph.disk.runAll()
        idle()
        assertEquals(View.GONE, a.findViewById<View>(R.id.detail_export_row).visibility)
        assertEquals(app.getString(R.string.export_cancelled), a.findViewById<TextView>(R.id.detail_message).text.toString())
        assertTrue(exportsLeft().toString(), exportsLeft().isEmpty())
        assertNull(shadowOf(a).nextStartedActivity)

        // A share let run to its end starts the chooser with the zip.
        a.findViewById<View>(R.id.detail_share).performClick()
        idle()
        graph.disk.runAll()
        idle()
        val chooser = shadowOf(a).nextStartedActivity
        assertEquals(Intent.ACTION_CHOOSER, chooser.action)
        assertEquals(listOf("$name.zip"), exportsLeft())

        // Half-way: the screen follows the export's progress (the export held at 40 % on its thread).
        val model = ViewModelProvider(a)[SessionDetailViewModel::class.java]
        val reported = CountDownLatch(1)
        val release = CountDownLatch(1)
        model.export({ "failed: $it" }, "cancelled") { _, progress ->
            progress.update(2, 5)
            reported.countDown()
            release.await()
            "done"
        }
        idle()
        val runner = Thread { graph.disk.runAll() }.apply { start() }
        reported.await()
        idle()
        assertEquals(app.getString(R.string.export_progress, 40), a.findViewById<TextView>(R.id.detail_export_text).text.toString())
        assertEquals(40, a.findViewById<LinearProgressIndicator>(R.id.detail_export_progress).progress)
        Screenshots.assertLaidOut(a, "detail-export-progress")
        Screenshots.captureWhole(a, "detail-export-progress")
        release.countDown()
        runner.join()
        idle()
        assertEquals("done", a.findViewById<TextView>(R.id.detail_message).text.toString())
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.pump()
        graph.settle()
        detail.pause().stop().destroy()
    }

    @Test
    fun `an export cancelled half-way stops at its next progress report and shows it`() {
        val model = SessionDetailViewModel(graph.graph, name)
        graph.settle()
        val reports = ArrayList<Pair<Long, Long>>()
        model.export({ "failed: $it" }, "cancelled") { _, progress ->
            progress.update(1, 4)
            reports += 1L to 4L
            model.cancelExport()
            progress.update(2, 4)
            reports += 2L to 4L
            "done"
        }
        idle()
        assertEquals(0f, model.state.value.exporting)
        graph.disk.runAll()
        idle()
        assertEquals(listOf(1L to 4L), reports)
        assertNull(model.state.value.exporting)
        assertEquals("cancelled", model.state.value.message)
    }

    @Test
    fun `a zip cut short by a cancel leaves nothing, and a whole one reports its progress to the end`() {
        val dir = offMainThread { File(app.filesDir, "sessions/$name") }
        val target = offMainThread { File(app.cacheDir, "exports/$name.zip") }
        val cut = runCatching {
            offMainThread { Exporter.writeZip(dir, target) { done, _ -> if (done > 0) throw CancellationException("cancelled") } }
        }.exceptionOrNull()
        assertTrue("$cut", cut is CancellationException)
        assertTrue(exportsLeft().toString(), exportsLeft().isEmpty())
        val seen = ArrayList<Pair<Long, Long>>()
        offMainThread { Exporter.writeZip(dir, target) { done, total -> seen += done to total } }
        val total = offMainThread { listOf("meta.json", "accelerometer.csv").sumOf { File(dir, it).length() } }
        assertTrue("${seen.size} reports", seen.size > 10)
        assertEquals(0L to total, seen.first())
        assertEquals(total to total, seen.last())
        assertTrue(seen.zipWithNext().all { (p, n) -> n.first >= p.first })
        assertEquals(listOf("$name.zip"), exportsLeft())
    }
}
