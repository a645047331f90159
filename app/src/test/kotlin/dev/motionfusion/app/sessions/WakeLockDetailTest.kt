package dev.motionfusion.app.sessions

import android.content.Intent
import android.view.View
import android.widget.TextView
import dev.motionfusion.app.R
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.offMainThread
import dev.motionfusion.app.record.CoreSessionFormat
import dev.motionfusion.app.record.Recorder
import dev.motionfusion.app.live.TestCapture
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.WakeLockUse
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.annotation.GraphicsMode
import java.io.File

/**
 * The session detail says which case of the recording's wake lock applied (meta.json `wake_lock`, docs/RECORDING.md
 * "Wake lock"): let go because every sensor batched in hardware, or held and which streams forced it; nothing for a
 * session that does not say (written before the member). English and German, rendered whole to PNG.
 */
@RunWith(RobolectricTestRunner::class)
@GraphicsMode(GraphicsMode.Mode.NATIVE)
class WakeLockDetailTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        graph = TestGraph()
    }

    /** A short closed session whose meta.json says [wakeLock]. */
    private fun session(name: String, wakeLock: WakeLockUse?): File {
        val dir = offMainThread { File(File(app.filesDir, "sessions"), name) }
        val meta = SessionMetadata(appVersion = "0.1.0", startAnchor = ClockAnchor(1_795_688_100_000L, 1_000_000_000L), filterSettings = FilterSettings(), wakeLock = wakeLock)
        val c = TestCapture()
        val recorder = Recorder(CoreSessionFormat.create(dir, meta), onEnd = {}, flushIntervalNs = 50_000_000L)
        c.record(recorder)
        for (i in 0 until 400) {
            val t = 1_000_000_000L + i * 5_000_000L
            c.offer(SessionStream.ACCELEROMETER, t, 0f, 0f, 9.81f)
            c.offer(SessionStream.GYROSCOPE, t + 1_000, 0f, 0f, 0f)
            if (i % 2 == 0) c.offer(SessionStream.MAGNETOMETER, t + 2_000, 20f, 0f, -40f)
            c.nowNs = t
        }
        c.drain()
        c.nowNs += 1_000_000_000L
        c.capture.pump()
        c.stop(recorder)
        return dir
    }

    private fun detail(dir: File): SessionDetailActivity {
        val intent = Intent(app, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, dir.name)
        val a = Robolectric.buildActivity(SessionDetailActivity::class.java, intent).setup().get()
        graph.settle()
        return a
    }

    private fun wakeLockLine(a: SessionDetailActivity): TextView = a.findViewById(R.id.detail_wake_lock)

    private val held = WakeLockUse(true, "not_wake_up", listOf(SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE_UNCALIBRATED))
    private val released = WakeLockUse(false, "hardware_batching")

    @Test
    fun `held and which streams forced it, let go, or nothing for an older session - English`() {
        RuntimeEnvironment.setQualifiers("w400dp-h860dp-xhdpi")
        val heldScreen = detail(session("held", held))
        val line = wakeLockLine(heldScreen)
        assertEquals(View.VISIBLE, line.visibility)
        assertEquals(
            "Wake lock held for the whole recording. No wake-up sensor that batches on this phone: magnetometer · gyroscope, uncalibrated.",
            line.text.toString(),
        )
        Screenshots.captureWhole(heldScreen, "session-detail-wake-lock-held-all")
        Screenshots.assertLaidOut(heldScreen, "session-detail-wake-lock-held")

        val releasedScreen = detail(session("released", released))
        assertEquals(View.VISIBLE, wakeLockLine(releasedScreen).visibility)
        assertEquals(
            "Wake lock let go while recording: every sensor batched in hardware and woke the phone itself.",
            wakeLockLine(releasedScreen).text.toString(),
        )
        Screenshots.captureWhole(releasedScreen, "session-detail-wake-lock-released-all")

        val small = detail(session("small", WakeLockUse(true, "fifo_too_small", listOf(SessionStream.ACCELEROMETER))))
        assertTrue(wakeLockLine(small).text.toString(), wakeLockLine(small).text.startsWith("Wake lock held for the whole recording. Hardware FIFO too small"))

        val older = detail(session("older", null))
        assertEquals("a session that does not say shows nothing", View.GONE, wakeLockLine(older).visibility)
        assertTrue(older.findViewById<TextView>(R.id.detail_streams).text.contains("accelerometer"))
    }

    @Test
    fun `the same in German`() {
        RuntimeEnvironment.setQualifiers("de-rDE-w400dp-h860dp-xhdpi")
        val heldScreen = detail(session("held", held))
        val text = wakeLockLine(heldScreen).text.toString()
        assertTrue(text, text.startsWith("Wake-Lock während der ganzen Aufnahme gehalten."))
        assertTrue(text, text.contains(heldScreen.getString(R.string.stream_magnetometer)))
        Screenshots.captureWhole(heldScreen, "de-session-detail-wake-lock-held-all")
        val releasedScreen = detail(session("released", released))
        assertTrue(wakeLockLine(releasedScreen).text.startsWith("Wake-Lock während der Aufnahme freigegeben"))
        Screenshots.captureWhole(releasedScreen, "de-session-detail-wake-lock-released-all")
    }
}
