package dev.motionfusion.app.record

import dev.motionfusion.app.platform.Sdks
import org.robolectric.annotation.Config
import dev.motionfusion.app.offMainThread
import dev.motionfusion.app.settings.LiveSettings
import dev.motionfusion.app.settings.RecordingLimits
import android.Manifest
import android.app.Activity
import android.content.Intent
import android.content.res.Configuration
import android.content.pm.PackageManager
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.view.View
import android.widget.Button
import android.widget.EditText
import android.widget.TextView
import androidx.appcompat.app.AlertDialog
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.sensor.GyroSaturation
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.session.Marker
import dev.motionfusion.core.session.SessionArchive
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.event.SessionStream
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
import org.robolectric.android.controller.ActivityController
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowDialog
import org.robolectric.shadows.ShadowPowerManager
import org.robolectric.shadows.ShadowSensorManager
import java.io.File
import java.time.Duration

/**
 * Recording as people expect it, on the real session format: markers from the record bar in the
 * exported zip, the notification permission explained once before the first recording, the
 * maximum duration and the battery stop on the fake clock and battery, the wake lock's renewal,
 * and the gyroscope saturation taken from the sensor's range into meta.json.
 */
@RunWith(RobolectricTestRunner::class)
class RecordingAsExpectedTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var sensors: ShadowSensorManager
    private lateinit var all: Map<SessionStream, Sensor>
    private lateinit var graph: TestGraph

    /** ±2000°/s gyroscope as phones report it, rad/s. */
    private val gyroRange = 34.906586f

    @Before
    fun setUp() {
        sensors = shadowOf(app.getSystemService(SensorManager::class.java))
        all = SensorStreams.all.associateWith { s ->
            val b = SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}")
            if (s == SessionStream.GYROSCOPE) b.setMaximumRange(gyroRange)
            b.build().also(sensors::addSensor)
        }
        graph = TestGraph()
    }

    private val state get() = graph.graph.recordings.state.value

    private fun sendRound(t: Long) = SensorStreams.all.forEachIndexed { i, s ->
        val values = FloatArray(s.valueCount) { k -> if (s == SessionStream.ACCELEROMETER && k == 2) 9.81f else 0.01f * (k + 1) }
        sensors.sendSensorEventToListeners(
            SensorEventBuilder.newBuilder().setSensor(all.getValue(s)).setValues(values).setTimestamp(t + i)
                .setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
        )
    }

    private fun startService(intent: Intent = Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START)) =
        Robolectric.buildService(RecordingService::class.java, intent).create().startCommand(0, 1).also { graph.settle() }

    private fun stop(service: RecordingService): RecordingState.Ended {
        service.onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        return awaitEnded()
    }

    private fun awaitEnded(): RecordingState.Ended {
        graph.pump()
        graph.settle()
        return state as? RecordingState.Ended ?: error("recording did not end; state $state")
    }

    private fun latestDialog(): AlertDialog = ShadowDialog.getLatestDialog() as AlertDialog

    private fun click(a: Activity, id: Int) {
        a.findViewById<Button>(id).performClick()
        shadowOf(Looper.getMainLooper()).idle()
    }

    private fun zipOf(dir: File): File = offMainThread { File(app.cacheDir, "${dir.name}.zip").also { SessionArchive.zip(dir.toPath(), it.toPath()) } }

    @Test
    fun `Mark on the record bar, tapped and long-pressed with a note, lands in the exported session`() {
        graph.graph.setNotificationsAnswered()
        val activity = Robolectric.buildActivity(MainActivity::class.java).setup()
        val a = activity.get()
        val mark = a.findViewById<Button>(R.id.record_mark)
        assertEquals("no Mark before recording", View.GONE, mark.visibility)
        click(a, R.id.record_toggle)
        val c = startService(shadowOf(app).nextStartedService)
        for (i in 0 until 50) sendRound(5_000_000_000L + i * 10_000_000L)
        graph.pump()
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertEquals(View.VISIBLE, mark.visibility)

        graph.clock.elapsedNs = 5_200_000_000L
        mark.performClick()
        graph.clock.elapsedNs = 5_300_000_000L
        assertTrue(mark.performLongClick())
        shadowOf(Looper.getMainLooper()).idle()
        val dialog = latestDialog()
        val hostile = "stairs, \"up\"\nsecond line " + "ü".repeat(500)
        dialog.findViewById<EditText>(R.id.record_mark_input)!!.setText(hostile)
        graph.clock.elapsedNs = 5_400_000_000L // the note is typed later; the marker keeps the press's time
        dialog.getButton(AlertDialog.BUTTON_POSITIVE).performClick()
        shadowOf(Looper.getMainLooper()).idle()
        for (i in 50 until 60) sendRound(5_000_000_000L + i * 10_000_000L)
        graph.pump()
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        val status = a.findViewById<TextView>(R.id.record_status).text.toString()
        assertTrue(status, status.contains("2 markers"))

        val ended = stop(c.get())
        val markers = SessionReader.open(zipOf(ended.session!!).toPath()).use { r ->
            assertEquals(2L, r.metadata.markers?.samples)
            r.markers()
        }
        // The dialog's field holds at most the format's 200 characters; the format makes the note one line.
        val expected = dev.motionfusion.core.session.SessionMarkers.label(hostile.take(200))
        assertEquals(listOf(Marker(5_200_000_000L, ""), Marker(5_300_000_000L, expected)), markers)
        assertTrue(expected.startsWith("stairs, \"up\" second line ü"))
        activity.pause().stop().destroy()
    }

    private fun recordingScreen(): ActivityController<MainActivity> = Robolectric.buildActivity(MainActivity::class.java).setup()

    @Test
    fun `Record after a 3-s countdown, shown, cancelled, kept through a rotation, and the session's first sample after it`() {
        graph.graph.setNotificationsAnswered()
        graph.graph.settingsRepository.update(LiveSettings(startDelayS = 3))
        val activity = recordingScreen()
        var a = activity.get()
        fun toggle() = a.findViewById<Button>(R.id.record_toggle).text.toString()
        fun status() = a.findViewById<TextView>(R.id.record_status).text.toString()
        click(a, R.id.record_toggle)
        assertEquals("Cancel (3)", toggle())
        assertEquals("Recording starts in 3 s: put the phone in place.", status())
        // Rendered in ScreensTest, LocaleScreensTest and ScaledScreensTest (live-countdown).
        // Cancelled: nothing starts, however long one waits.
        click(a, R.id.record_toggle)
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(5))
        assertNull(shadowOf(app).peekNextStartedService())
        assertEquals("Record", toggle())
        assertEquals(RecordingState.Idle, state)

        // Again, rotated in the middle, and left to run out.
        click(a, R.id.record_toggle)
        val pressedMs = android.os.SystemClock.uptimeMillis()
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        for (i in 0 until 50) sendRound(5_000_000_000L + i * 10_000_000L) // while counting down
        graph.pump()
        activity.configurationChange(Configuration(app.resources.configuration).apply { orientation = Configuration.ORIENTATION_LANDSCAPE })
        shadowOf(Looper.getMainLooper()).idle()
        a = activity.get()
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofMillis(600)) // the bar's refresh
        assertEquals("Cancel (2)", toggle())
        // The service starts 3 s after the press, not before (the main looper's clock, 100 ms a step).
        while (shadowOf(app).peekNextStartedService() == null) {
            val waited = android.os.SystemClock.uptimeMillis() - pressedMs
            check(waited < 10_000) { "the countdown never ended: ${toggle()}" }
            shadowOf(Looper.getMainLooper()).idleFor(Duration.ofMillis(100))
        }
        val waited = android.os.SystemClock.uptimeMillis() - pressedMs
        assertTrue("started after $waited ms", waited in 3_000L..3_100L)
        val c = startService(shadowOf(app).nextStartedService)
        assertTrue(graph.graph.recordings.isRecording)
        for (i in 50 until 100) sendRound(5_000_000_000L + i * 10_000_000L)
        val ended = stop(c.get())
        val first = offMainThread {
            SessionReader.open(ended.session!!.toPath()).use { r -> r.stream(SessionStream.GYROSCOPE).use { e -> e.next(); e.timestampNs } }
        }
        assertTrue("first sample $first, the countdown ended after 5,490,000,000", first >= 5_500_000_000L)
        activity.pause().stop().destroy()
    }

    @Test
    fun `the sensors chosen are recorded and listed in meta_json, the filter's own whatever the choice`() {
        val sensorStreams = SensorStreams.all.toSet()
        fun record(settings: LiveSettings): Pair<Set<SessionStream>, Set<SessionStream>> {
            graph.graph.settingsRepository.update(settings)
            val c = startService()
            for (i in 0 until 20) sendRound(5_000_000_000L + i * 10_000_000L)
            graph.pump()
            val ended = stop(c.get())
            return offMainThread {
                SessionReader.open(ended.session!!.toPath()).use { r -> r.metadata.sensors.map { it.stream }.toSet() to (r.streams intersect sensorStreams) }
            }
        }
        val acc = SessionStream.ACCELEROMETER
        val gyro = SessionStream.GYROSCOPE
        // Nothing optional chosen, 9D: the magnetometer is the filter's.
        val nineD = setOf(acc, gyro, SessionStream.MAGNETOMETER)
        assertEquals(nineD to nineD, record(LiveSettings(optionalStreams = emptySet())))
        // 6D with the rotation vector chosen: no magnetometer.
        val sixD = setOf(acc, gyro, SessionStream.ROTATION_VECTOR)
        val imu = LiveSettings.DEFAULT_FILTER.copy(mode = dev.motionfusion.core.filter.FilterMode.IMU)
        assertEquals(sixD to sixD, record(LiveSettings(filter = imu, optionalStreams = setOf(SessionStream.ROTATION_VECTOR))))
        // The default: every stream, as before the choice existed.
        assertEquals(sensorStreams to sensorStreams, record(LiveSettings()))
    }

    @Test
    fun `a countdown is cancelled when the screen is left`() {
        graph.graph.setNotificationsAnswered()
        graph.graph.settingsRepository.update(LiveSettings(startDelayS = 10))
        val activity = recordingScreen()
        click(activity.get(), R.id.record_toggle)
        assertTrue(graph.graph.recordings.countdown.isRunning)
        activity.pause().stop()
        assertFalse(graph.graph.recordings.countdown.isRunning)
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(11))
        assertNull(shadowOf(app).peekNextStartedService())
        activity.destroy()
    }

    @Test
    @Config(minSdk = 33, maxSdk = Sdks.MAX)
    fun `API 33+, the first Record explains the notification, then asks, recording starts whatever the answer and it is not asked again`() {
        val activity = recordingScreen()
        val a = activity.get()
        click(a, R.id.record_toggle)
        val dialog = latestDialog()
        assertTrue(dialog.isShowing)
        val text = dialog.findViewById<TextView>(android.R.id.message)!!.text.toString()
        assertTrue(text, text.contains("Stop button") && text.contains("recording works all the same"))
        assertNull("nothing asked or started before the explanation is answered", shadowOf(a).lastRequestedPermission)
        assertNull(shadowOf(app).peekNextStartedService())

        dialog.getButton(AlertDialog.BUTTON_POSITIVE).performClick()
        shadowOf(Looper.getMainLooper()).idle()
        val request = shadowOf(a).lastRequestedPermission!!
        assertEquals(Manifest.permission.POST_NOTIFICATIONS, request.requestedPermissions.single())
        // Denied.
        a.onRequestPermissionsResult(request.requestCode, request.requestedPermissions, intArrayOf(PackageManager.PERMISSION_DENIED))
        shadowOf(Looper.getMainLooper()).idle()
        val c = startService(shadowOf(app).nextStartedService)
        assertTrue(graph.graph.recordings.isRecording)
        a.findViewById<View>(R.id.record_bar).let { shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1)) }
        val status = a.findViewById<TextView>(R.id.record_status).text.toString()
        assertTrue(status, status.contains("notification may be hidden"))
        // The way back: the app's notification settings.
        val turnOn = a.findViewById<Button>(R.id.record_notifications_on)
        assertEquals(View.VISIBLE, turnOn.visibility)
        turnOn.performClick()
        val settings = shadowOf(a).nextStartedActivity
        assertEquals(android.provider.Settings.ACTION_APP_NOTIFICATION_SETTINGS, settings.action)
        assertEquals(app.packageName, settings.getStringExtra(android.provider.Settings.EXTRA_APP_PACKAGE))
        stop(c.get())

        // The next Record starts at once: no explanation, no question.
        val before = ShadowDialog.getShownDialogs().size
        click(a, R.id.record_toggle)
        assertEquals(before, ShadowDialog.getShownDialogs().size)
        assertNotNull(shadowOf(app).nextStartedService)
        activity.pause().stop().destroy()
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = 32)
    fun `before API 33, Record starts at once, as notifications need no permission there`() {
        val activity = recordingScreen()
        val before = ShadowDialog.getShownDialogs().size
        click(activity.get(), R.id.record_toggle)
        assertEquals("no explanation", before, ShadowDialog.getShownDialogs().size)
        assertNull("nothing asked", shadowOf(activity.get()).lastRequestedPermission)
        assertNotNull(shadowOf(app).nextStartedService)
        activity.pause().stop().destroy()
    }

    @Test
    @Config(minSdk = 33, maxSdk = Sdks.MAX)
    fun `API 33+, recording without notifications from the explanation also asks only once`() {
        val activity = recordingScreen()
        click(activity.get(), R.id.record_toggle)
        latestDialog().getButton(AlertDialog.BUTTON_NEGATIVE).performClick()
        shadowOf(Looper.getMainLooper()).idle()
        assertNull(shadowOf(activity.get()).lastRequestedPermission)
        assertNotNull(shadowOf(app).nextStartedService)
        assertTrue(graph.graph.notificationsAnswered)
        // Without notifications: the bar offers to turn them on.
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertEquals(View.VISIBLE, activity.get().findViewById<View>(R.id.record_notifications_on).visibility)
        activity.pause().stop().destroy()
    }

    @Test
    fun `the maximum duration stops the recording on the injected clock and meta json says why`() {
        graph.graph.settingsRepository.update(LiveSettings(limits = RecordingLimits(maxDurationS = 15 * 60L, stopBatteryPercent = 0)))
        val start = graph.clock.elapsedNs
        val c = startService()
        sendRound(start + 1_000_000L)
        graph.pump()
        graph.clock.elapsedNs = start + 15 * 60 * 1_000_000_000L - 1
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertTrue("still recording just before the limit", graph.graph.recordings.isRecording)
        graph.clock.elapsedNs = start + 15 * 60 * 1_000_000_000L
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        val ended = awaitEnded()
        assertEquals(RecordingEnd.MaxDuration(900L), ended.result.end)
        SessionReader.open(ended.session!!.toPath()).use { assertEquals("max_duration", it.metadata.endReason) }
        assertTrue(shadowOf(c.get()).isStoppedBySelf)
    }

    @Test
    fun `the Noise recording has its own limits, not the user's maximum duration or battery level`() {
        graph.graph.settingsRepository.update(LiveSettings(limits = RecordingLimits(maxDurationS = 5 * 60L, stopBatteryPercent = 30)))
        graph.battery.state = BatteryState(20, charging = false)
        val start = graph.clock.elapsedNs
        startService(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START).putExtra(RecordingService.EXTRA_STILL, true))
        sendRound(start + 1_000_000L)
        graph.pump()
        graph.clock.elapsedNs = start + 3 * 3600 * 1_000_000_000L - 1
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertTrue("past the user's 5 min and below their 30 %: still recording", graph.graph.recordings.isRecording)
        graph.clock.elapsedNs = start + 3 * 3600 * 1_000_000_000L
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        val ended = awaitEnded()
        assertEquals(RecordingEnd.MaxDuration(RecordingLimits.STILL.maxDurationS), ended.result.end)
        assertTrue(ended.still)
    }

    @Test
    fun `a low battery stops the recording unless it is charging, and meta json says why`() {
        graph.graph.settingsRepository.update(LiveSettings(limits = RecordingLimits(stopBatteryPercent = 10)))
        graph.battery.state = BatteryState(10, charging = true)
        startService()
        sendRound(graph.clock.elapsedNs + 1_000_000L)
        graph.pump()
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(2))
        assertTrue("charging: goes on", graph.graph.recordings.isRecording)
        assertTrue(graph.battery.reads > 0)
        graph.battery.state = BatteryState(11, charging = false)
        graph.clock.elapsedNs += 31_000_000_000L
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertTrue("above the level: goes on", graph.graph.recordings.isRecording)
        graph.battery.state = BatteryState(10, charging = false)
        graph.clock.elapsedNs += 31_000_000_000L
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        val ended = awaitEnded()
        assertEquals(RecordingEnd.BatteryLow(10), ended.result.end)
        SessionReader.open(ended.session!!.toPath()).use { assertEquals("battery_low", it.metadata.endReason) }
        val message = RecordingService.endMessage(app, ended.result)
        assertTrue(message, message.contains("battery is at 10\u00A0%"))
    }

    @Test
    fun `the wake lock is partial, renewed every minute of the injected clock while recording, and released at the end`() {
        val c = startService()
        val lock = ShadowPowerManager.getLatestWakeLock()
        assertTrue(lock.isHeld)
        val held = shadowOf(lock).timesHeld
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(5))
        assertEquals("not renewed before a minute", held, shadowOf(lock).timesHeld)
        graph.clock.elapsedNs += RecordingService.WAKE_LOCK_RENEW_NS
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertEquals("renewed", held + 1, shadowOf(lock).timesHeld)
        graph.clock.elapsedNs += RecordingService.WAKE_LOCK_RENEW_NS
        shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1))
        assertEquals(held + 2, shadowOf(lock).timesHeld)
        stop(c.get())
        assertFalse("released", lock.isHeld)
    }

    @Test
    fun `the gyroscope's range sets the filter's default saturation, live and in meta json`() {
        val expected = gyroRange * GyroSaturation.MARGIN
        assertEquals(expected, graph.capture.filterSettingsFor(graph.graph.settings.value).gyroSaturation!!, 1e-6)
        val c = startService()
        sendRound(graph.clock.elapsedNs + 1_000_000L)
        graph.pump()
        assertEquals(expected, graph.capture.filterSettingsInUse().gyroSaturation!!, 1e-6)
        val ended = stop(c.get())
        SessionReader.open(ended.session!!.toPath()).use { assertEquals(expected, it.metadata.filterSettings!!.gyroSaturation!!, 1e-6) }
        // A value the user chose, or off, is used as set: the range stands in for the default only.
        val chosen = graph.graph.settings.value.let { it.copy(filter = it.filter.copy(gyroSaturation = 20.0)) }
        assertEquals(20.0, graph.capture.filterSettingsFor(chosen).gyroSaturation!!, 0.0)
        assertNull(graph.capture.filterSettingsFor(chosen.copy(filter = chosen.filter.copy(gyroSaturation = null))).gyroSaturation)
        // A range no gyroscope has keeps the filter's default.
        assertNull(GyroSaturation.fromRange(0f))
        assertNull(GyroSaturation.fromRange(Float.NaN))
        assertNull(GyroSaturation.fromRange(null))
        // A driver that reports its range in °/s gets the same threshold as one in rad/s.
        assertEquals(Math.toRadians(2000.0) * GyroSaturation.MARGIN, GyroSaturation.fromRange(2000f)!!, 1e-9)
        assertEquals(GyroSaturation.fromRange(Math.toRadians(2000.0).toFloat())!!, GyroSaturation.fromRange(2000f)!!, 1e-5)
        assertEquals(Math.toRadians(125.0) * GyroSaturation.MARGIN, GyroSaturation.fromRange(125f)!!, 1e-9)
        assertEquals(69.8 * GyroSaturation.MARGIN, GyroSaturation.fromRange(69.8f)!!, 1e-5)
    }
}
