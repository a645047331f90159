package dev.motionfusion.app

import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.view.accessibility.AccessibilityEvent
import android.view.accessibility.AccessibilityManager
import dev.motionfusion.app.live.LiveScreen
import dev.motionfusion.app.record.RecorderResult
import dev.motionfusion.app.record.RecordingEnd
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.core.event.SessionStream
import org.junit.Assert.assertEquals
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.shadows.SensorBuilder
import java.io.File
import java.time.Duration

/**
 * What TalkBack hears: the recording's state announced once per change (not at each refresh of
 * the record bar or the banner), and the live screen's descriptions of the angles, the attitude
 * indicator and the compass given new words at most every 2 s of sample time, in whole degrees,
 * however fast the phone moves (before, each was rewritten at every frame).
 */
@RunWith(RobolectricTestRunner::class)
class AccessibilityEventsTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var graph: TestGraph

    @Before
    fun setUp() {
        val sm = shadowOf(app.getSystemService(SensorManager::class.java))
        for (type in listOf(Sensor.TYPE_ACCELEROMETER, Sensor.TYPE_GYROSCOPE, Sensor.TYPE_MAGNETIC_FIELD, Sensor.TYPE_ROTATION_VECTOR)) {
            sm.addSensor(SensorBuilder.newBuilder().setType(type).setName("Test $type").build())
        }
        graph = TestGraph()
        shadowOf(app.getSystemService(AccessibilityManager::class.java)).setEnabled(true)
    }

    private fun announcements(): List<String> = shadowOf(app.getSystemService(AccessibilityManager::class.java)).sentAccessibilityEvents
        .filter { it.eventType == AccessibilityEvent.TYPE_ANNOUNCEMENT }.map { it.text.joinToString("") }

    private fun tick(seconds: Long) {
        graph.clock.elapsedNs += seconds * 1_000_000_000L
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(seconds))
    }

    @Test
    fun `the recording's state is announced once per change, on the live screen and the others`() {
        val live = Robolectric.buildActivity(MainActivity::class.java).setup()
        val settings = Robolectric.buildActivity(dev.motionfusion.app.settings.SettingsActivity::class.java).setup()
        graph.settle()
        val recordings = graph.graph.recordings
        recordings.set(RecordingState.Preparing(0, 0))
        tick(1)
        recordings.set(RecordingState.Active(File("sessions", "session_now"), graph.clock.elapsedNs / 1_000_000, rows = { 41_522L }, streams = 4))
        for (s in 1..30) tick(1) // the bar refreshes twice a second, the banner every second
        recordings.set(RecordingState.Ended(null, RecorderResult(RecordingEnd.Stopped, LongArray(SessionStream.entries.size), 0), false))
        for (s in 1..5) tick(1)
        val a = live.get()
        val started = listOf(a.getString(R.string.record_preparing), a.getString(R.string.record_announce_started))
        val ended = a.getString(R.string.record_announce_ended, a.getString(R.string.record_end_stopped, 0))
        // The live screen's record bar and the settings screen's banner: each says each change once.
        assertEquals(listOf(started[0], started[0], started[1], started[1], ended, ended), announcements())
        settings.destroy()
        live.destroy()
    }

    @Test
    fun `the live screen's descriptions change at most every 2 s, in whole degrees`() {
        val a = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        graph.settle()
        val screen = LiveScreen(a, graph.capture.sensorInfo)
        LiveStates.sway(screen) // 12 s at 60 frames/s: 721 frames, every angle changing
        // Three descriptions, each at most once per 2 s of the 12 s (and once at the start): at most 21, not 3 × 721.
        assertTrue("${screen.descriptionUpdates} descriptions", screen.descriptionUpdates in 3..21)
        val compass = a.findViewById<View>(R.id.compass).contentDescription.toString()
        assertTrue(compass, Regex("""Compass: heading \d+°""").matches(compass))
        val attitude = a.findViewById<View>(R.id.attitude).contentDescription.toString()
        assertTrue(attitude, Regex("""Attitude indicator: pitch -?\d+°, roll -?\d+°""").matches(attitude))
    }
}
