package dev.motionfusion.app.record

import android.os.Build
import dev.motionfusion.app.platform.Sdks
import org.robolectric.annotation.Config
import dev.motionfusion.app.offMainThread

import dev.motionfusion.core.event.SessionStream
import android.app.Notification
import android.app.NotificationManager
import android.content.Intent
import android.content.pm.ServiceInfo
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import android.widget.Button
import dev.motionfusion.app.MainActivity
import dev.motionfusion.app.R
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.sensor.SensorStreams
import org.junit.After
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNotNull
import org.junit.Assert.assertTrue
import org.junit.Before
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.android.controller.ServiceController
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowPowerManager
import org.robolectric.shadows.ShadowSensorManager
import java.io.File
import android.app.Service
import android.widget.TextView
import dev.motionfusion.app.Screenshots
import dev.motionfusion.app.sessions.SessionsActivity
import org.junit.Assert.assertNotEquals
import org.junit.Assert.assertNull
import org.robolectric.annotation.GraphicsMode
import org.robolectric.shadows.ShadowLog
import dev.motionfusion.app.platform.Foreground

/** The recording service with the sensors ShadowSensorManager provides and a test double of the session format. */
@RunWith(RobolectricTestRunner::class)
class RecordingServiceTest {
    private val app = RuntimeEnvironment.getApplication()
    private lateinit var sensors: ShadowSensorManager
    private lateinit var all: Map<SessionStream, Sensor>
    private val format = LineFormat()

    private lateinit var graph: TestGraph
    private var refusal: RuntimeException? = null

    @Before
    fun setUp() {
        sensors = shadowOf(app.getSystemService(SensorManager::class.java))
        all = SensorStreams.all.associateWith { s ->
            SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}").build().also(sensors::addSensor)
        }
        graph = graph(format)
    }

    private fun graph(f: SessionFormat) = TestGraph(format = f, enterForeground = { service, id, n, type ->
        refusal?.let { throw it }
        androidx.core.app.ServiceCompat.startForeground(service, id, n, type)
    })

    private val state get() = graph.graph.recordings.state.value

    private fun idle() = graph.settle()

    private fun send(stream: SessionStream, t: Long) {
        val values = FloatArray(stream.valueCount) { (t % 1000).toFloat() + it }
        sensors.sendSensorEventToListeners(
            SensorEventBuilder.newBuilder().setSensor(all.getValue(stream)).setValues(values).setTimestamp(t)
                .setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
        )
    }

    private fun sendRound(t: Long) = SensorStreams.all.forEachIndexed { i, s -> send(s, t + i) }

    private fun startService(intent: Intent = Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START)):
        ServiceController<RecordingService> {
        val c = Robolectric.buildService(RecordingService::class.java, intent).create().startCommand(0, 1)
        idle()
        return c
    }

    private fun awaitEnded(): RecordingState.Ended {
        graph.pump()
        idle()
        return state as? RecordingState.Ended ?: error("recording did not end; state $state")
    }

    private fun rows(): Long {
        graph.pump()
        return (state as? RecordingState.Active ?: error("not recording: $state")).rows()
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `start goes foreground as specialUse with a wake lock and listens to every stream`() {
        val c = startService()
        val service = shadowOf(c.get())
        assertNotNull(service.lastForegroundNotification)
        // Types exist from API 29 and are required from 34: below 34 the service starts without one.
        if (Build.VERSION.SDK_INT >= 29) {
            val expected = if (Build.VERSION.SDK_INT >= 34) ServiceInfo.FOREGROUND_SERVICE_TYPE_SPECIAL_USE else 0
            assertEquals(expected, c.get().foregroundServiceType)
        }
        // The channels exist on every version (API 26+), the recording's one quiet.
        val nm = app.getSystemService(android.app.NotificationManager::class.java)
        assertEquals(android.app.NotificationManager.IMPORTANCE_LOW, nm.getNotificationChannel(RecordingService.CHANNEL_RECORDING).importance)
        assertNotNull(nm.getNotificationChannel(RecordingService.CHANNEL_ALERTS))
        assertEquals(RecordingService.CHANNEL_RECORDING, service.lastForegroundNotification.channelId)
        val lock = ShadowPowerManager.getLatestWakeLock()
        assertTrue("partial wake lock held", lock.isHeld)
        val listener = sensors.listeners.single()
        all.values.forEach { assertTrue(sensors.hasListener(listener, it)) }
        assertTrue(graph.graph.recordings.isRecording)
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        awaitEnded()
        assertFalse("wake lock released", lock.isHeld)
        assertTrue(sensors.listeners.isEmpty())
        assertTrue(service.isForegroundStopped)
        assertTrue(service.isStoppedBySelf)
    }

    @Test
    fun `the wake lock is taken when Record is pressed, before the recording is prepared, and let go when it is refused`() {
        val c = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START))
            .create().startCommand(0, 1)
        shadowOf(Looper.getMainLooper()).idle()
        // Preparation (repair, the new session's files) still waits on the recording's queue.
        assertTrue(graph.recordingDisk.pending > 0)
        assertTrue(state is RecordingState.Preparing)
        val lock = ShadowPowerManager.getLatestWakeLock()
        assertNotNull("a wake lock from the press", lock)
        assertTrue(lock.isHeld)
        idle()
        assertTrue(state is RecordingState.Active)
        assertTrue(lock.isHeld)
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        awaitEnded()
        assertFalse(lock.isHeld)
        refusal = IllegalStateException("startForeground() not allowed due to mAllowStartForeground false")
        startService()
        assertTrue(state is RecordingState.NotStarted)
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
    }

    @Test
    fun `keeps recording after the activity is destroyed, and Stop in the notification ends it with every sample`() {
        // The notification explanation was answered before (RecordingAsExpectedTest covers it).
        graph.graph.setNotificationsAnswered()
        val activity = Robolectric.buildActivity(MainActivity::class.java).setup()
        activity.get().findViewById<Button>(R.id.record_toggle).performClick()
        val started = shadowOf(app).nextStartedService
        assertEquals(RecordingService.ACTION_START, started.action)
        val c = startService(started)
        for (i in 0 until 100) sendRound(1_000_000_000L + i * 5_000_000L)
        activity.pause().stop().destroy()
        idle()
        for (i in 100 until 300) sendRound(1_000_000_000L + i * 5_000_000L)
        assertEquals(300L * SensorStreams.all.size, rows())
        assertTrue("still recording", graph.graph.recordings.isRecording)

        // The elapsed time and the sample count are in the notification, which has Stop; it is updated every 5 s.
        shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(RecordingService.NOTIFICATION_UPDATE_TICKS))
        val nm = app.getSystemService(NotificationManager::class.java)
        val n: Notification = shadowOf(nm).getNotification(RecordingService.NOTIFICATION_ID)
        val text = n.extras.getCharSequence(Notification.EXTRA_TEXT).toString()
        assertTrue(text, text.contains("2,400 samples"))
        assertTrue(n.flags and Notification.FLAG_ONGOING_EVENT != 0)
        val stop = n.actions.single { it.title == app.getString(R.string.record_stop) }
        val stopIntent = shadowOf(stop.actionIntent).savedIntent
        assertEquals(RecordingService.ACTION_STOP, stopIntent.action)
        c.get().onStartCommand(stopIntent, 0, 2)
        val ended = awaitEnded()
        assertEquals(RecordingEnd.Stopped, ended.result.end)
        assertEquals(2400L, ended.result.rows)
        val dir = format.created!!
        val rows = LineFormat.rows(dir).filterNot { it.startsWith("FUSED") }
        assertEquals(2400, rows.size)
        assertTrue(File(dir, "finished").exists())
        // Every stream in order of timestamps as sent.
        val times = rows.map { it.split(',')[1].toLong() }
        assertEquals(times.sorted(), times)
        assertTrue("sessions are in app-private storage", dir.startsWith(File(app.filesDir, "sessions")))
    }

    @Test
    fun `a foreground start the system refuses is shown to the user in their language, the system's words only in the log, and records nothing`() {
        for ((refusal, kind) in listOf(
            SecurityException("Starting FGS with type specialUse requires permissions") to Foreground.Refusal.PERMISSION,
            IllegalStateException("startForeground() not allowed due to mAllowStartForeground false") to Foreground.Refusal.BACKGROUND,
        )) {
            this.refusal = refusal
            val before = File(app.filesDir, "sessions").list()?.size ?: 0
            val c = startService()
            val state = this.state
            assertEquals(RecordingState.NotStarted(kind), state)
            assertTrue("logged", ShadowLog.getLogsForTag("Foreground").any { it.throwable === refusal })
            assertTrue(shadowOf(c.get()).isStoppedBySelf)
            assertTrue(sensors.listeners.isEmpty())
            assertEquals(before, File(app.filesDir, "sessions").list()?.size ?: 0)
            val nm = app.getSystemService(NotificationManager::class.java)
            val text = shadowOf(nm).getNotification(RecordingService.END_NOTIFICATION_ID).extras.getCharSequence(Notification.EXTRA_TEXT).toString()
            assertEquals(app.getString(R.string.record_not_started, app.getString(kind.text)), text)
            assertFalse(text, text.contains(refusal.message!!))
        }
        // The main screen says it too (built last: its live view listens to the sensors).
        val main = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        assertEquals(
            app.getString(R.string.record_not_started, app.getString(R.string.foreground_refused_background)),
            main.findViewById<android.widget.TextView>(R.id.record_status).text.toString(),
        )
    }

    @Test
    fun `storage failure stops cleanly, keeps what was written and tells the user`() {
        graph = graph(LineFormat(failAfterBytes = 20_000))
        startService()
        for (i in 0 until 2000) {
            sendRound(1_000_000_000L + i * 5_000_000L)
            if (i % 100 == 0) graph.capture.pump()
        }
        val ended = awaitEnded()
        val end = ended.result.end
        assertTrue(end.toString(), end is RecordingEnd.WriteFailed)
        assertTrue(ShadowPowerManager.getLatestWakeLock().let { !it.isHeld })
        assertTrue(sensors.listeners.isEmpty())
        // Recovered in place: the partial line cut off; every complete row is a prefix of what was sent.
        val dir = ended.session!!
        assertTrue(File(dir, "recovered").exists())
        val rows = LineFormat.rows(dir)
        assertTrue(rows.size > 100)
        assertTrue(File(dir, "rows.txt").length() <= 20_000)
        val times = rows.filterNot { it.startsWith("FUSED") }.map { it.split(',')[1].toLong() }
        val sent = (0 until 2000).flatMap { i -> SensorStreams.all.indices.map { 1_000_000_000L + i * 5_000_000L + it } }
        assertEquals(sent.take(times.size), times)
        // The user is told, in a notification and on the main screen.
        val nm = app.getSystemService(NotificationManager::class.java)
        val alert = shadowOf(nm).getNotification(RecordingService.END_NOTIFICATION_ID)
        val text = alert.extras.getCharSequence(Notification.EXTRA_TEXT).toString()
        assertEquals(app.getString(R.string.record_end_write_failed, ended.result.rows), text)
        // The system's words go to the log, not to the user.
        assertFalse(text, text.contains("No space left on device"))
        assertTrue(ShadowLog.getLogsForTag("RecordingService").any { "No space left on device" in it.msg })
        val main = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        assertEquals(text, main.findViewById<android.widget.TextView>(R.id.record_status).text.toString())
    }

    @Test
    fun `an interrupted session is recovered on the next start`() {
        val root = File(app.filesDir, "sessions")
        val old = File(root, "session_2026-01-01_00-00-00").apply { mkdirs() }
        File(old, "rows.txt").writeText("ACCELEROMETER,1,3,0.0,0.0,9.81\nGYROSCOPE,2,3,0.0,0.")
        val c = startService()
        assertTrue(File(old, "recovered").exists())
        assertEquals(listOf("ACCELEROMETER,1,3,0.0,0.0,9.81"), LineFormat.rows(old))
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        awaitEnded()
    }

    @Test
    fun `Record after killed hour-long recordings repairs them on the disk executor, no main-thread task longer than a frame, progress shown`() {
        val root = File(app.filesDir, "sessions")
        offMainThread {
            for (k in 1..3) File(root, "session_2026-01-0${k}_00-00-00").apply { mkdirs() }.let { File(it, "rows.txt").writeText("GYROSCOPE,$k,3,0.0,0.") }
        }
        val repairThreads = ArrayList<Thread>()
        val slow = object : SessionFormat by format {
            override fun recover(dir: File) {
                repairThreads += Thread.currentThread()
                // Each repair takes, on the injected clock, what a killed one-hour recording's does (seconds).
                graph.clock.elapsedNs += REPAIR_OF_AN_HOUR_NS
                format.recover(dir)
            }
        }
        graph = graph(slow)
        val main = Robolectric.buildActivity(MainActivity::class.java).setup().get()
        val status = main.findViewById<android.widget.TextView>(R.id.record_status)
        val pressedNs = graph.clock.elapsedNs
        val c = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START))
            .create().startCommand(0, 1)
        val pressNs = graph.clock.elapsedNs - pressedNs
        // The press returned at once: nothing was repaired on the main thread, the work waits on the recording's disk queue.
        assertTrue(graph.recordingDisk.pending > 0)
        assertTrue(repairThreads.isEmpty())
        shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(600))
        assertEquals(app.getString(R.string.record_preparing), status.text.toString())
        assertTrue(state is RecordingState.Preparing)
        // Until the recording runs, each main-thread task is measured on the clock the repairs advance.
        val (longestNs, tasks) = graph.settleTimed()
        assertEquals(3, repairThreads.size)
        assertTrue("repaired off the main thread", repairThreads.none { it === Looper.getMainLooper().thread })
        assertTrue("main-thread tasks seen: $tasks", tasks > 0)
        assertTrue("the press blocked the main thread ${pressNs / 1e6} ms", pressNs <= FRAME_NS)
        assertTrue("a main-thread task took ${longestNs / 1e6} ms", longestNs <= FRAME_NS)
        assertEquals("the repairs' time passed (off the main thread)", 3 * REPAIR_OF_AN_HOUR_NS, graph.clock.elapsedNs - pressedNs)
        assertTrue(state is RecordingState.Active)
        shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(600))
        assertEquals(app.getString(R.string.record_stop), main.findViewById<Button>(R.id.record_toggle).text.toString())
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        awaitEnded()
    }


    /** The process dies: its sensor listeners go with it; the next graph is a new process's (only the files stay). */
    private fun kill() {
        val sm = app.getSystemService(SensorManager::class.java)
        sensors.listeners.toList().forEach { sm.unregisterListener(it) }
        graph = graph(format)
    }

    /** The system restarts the sticky service in the new process: onStartCommand with a null intent. */
    private fun restart(): ServiceController<RecordingService> {
        val c = Robolectric.buildService(RecordingService::class.java, null).create()
        assertEquals(Service.START_STICKY, c.get().onStartCommand(null, Service.START_FLAG_RETRY, 1))
        return c
    }

    private fun sessions(): List<File> = offMainThread { File(app.filesDir, "sessions").listFiles()?.sortedBy { it.name } ?: emptyList() }

    private fun inProgressFile() = File(app.filesDir, RecordingInProgress.FILE_NAME)

    // A recording the system kills and restarts (START_STICKY, a null intent): it resumes as a linked
    // continuation and the user is told; one the user stopped does not; a refused restart is told. The
    // "kill" drops the process's state: the sensor listeners go, a new object graph is made (a new
    // process), and only what is on storage remains.

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    @GraphicsMode(GraphicsMode.Mode.NATIVE)
    fun `a killed recording resumes in a linked session with the gap, told in the notification and the app`() {
        startService()
        for (i in 0 until 200) sendRound(3_000_000_000L + i * 5_000_000L)
        graph.pump()
        val before = (state as RecordingState.Active).session
        assertTrue("kept for a resumption", offMainThread { inProgressFile().isFile })
        // The process dies with a partial row at the end of the file.
        offMainThread { File(before, "rows.txt").appendText("GYROSCOPE,99,3,0.") }
        kill()
        assertEquals(RecordingState.Idle, state)
        graph.clock.elapsedNs += 41_000_000_000L // the last sample before was at 3.995 s, the new process's clock reads 5 s
        val resumedAt = graph.clock.elapsedNs
        val c = restart()
        // The restart holds the wake lock and is in the foreground at once, as a start is.
        assertTrue(ShadowPowerManager.getLatestWakeLock().isHeld)
        assertTrue(state.toString(), (state as RecordingState.Preparing).resuming)
        assertNotNull(shadowOf(c.get()).lastForegroundNotification)
        if (Build.VERSION.SDK_INT >= 29) {
            assertEquals(if (Build.VERSION.SDK_INT >= 34) ServiceInfo.FOREGROUND_SERVICE_TYPE_SPECIAL_USE else 0, c.get().foregroundServiceType)
        }
        assertEquals(
            app.getString(R.string.record_resuming),
            shadowOf(c.get()).lastForegroundNotification.extras.getCharSequence(Notification.EXTRA_SUB_TEXT).toString(),
        )
        graph.settle()
        val active = state as? RecordingState.Active ?: error("not resumed: $state")
        val after = active.session
        assertNotEquals(before, after)
        // The earlier part is repaired (its partial row cut) and named by the new one with the gap.
        assertTrue(offMainThread { File(before, "recovered").isFile })
        val lastBefore = offMainThread { LineFormat.rows(before).last().split(',')[1].toLong() }
        val continues = format.metadata!!.continues!!
        assertEquals(before.name, continues.previousSession)
        assertEquals(lastBefore, continues.gapStartElapsedRealtimeNs)
        assertEquals(resumedAt, continues.gapEndElapsedRealtimeNs)
        assertEquals(continues, active.continues)
        // The same recording: its start time (limits and chronometer count from it) is kept.
        assertEquals(5_000L, active.startedElapsedMs)
        // It records.
        for (i in 0 until 100) sendRound(50_000_000_000L + i * 5_000_000L)
        graph.pump()
        assertEquals(100L * SensorStreams.all.size, active.rows())
        // Told: the notification, the record bar, the banner of the other screens.
        shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofSeconds(1))
        val gap = RecordingService.gapText(continues)
        assertEquals("00:42", gap)
        val n = shadowOf(app.getSystemService(NotificationManager::class.java)).getNotification(RecordingService.NOTIFICATION_ID)
        assertEquals(app.getString(R.string.record_resumed_short, gap), n.extras.getCharSequence(Notification.EXTRA_SUB_TEXT).toString())
        if (Build.VERSION.SDK_INT == Sdks.MAX) {
            graph.graph.setNotificationsAnswered()
            val main = Robolectric.buildActivity(MainActivity::class.java).setup()
            shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(600))
            val status = main.get().findViewById<TextView>(R.id.record_status).text.toString()
            assertTrue(status, status.contains(app.getString(R.string.record_resumed, gap)))
            Screenshots.assertLaidOut(main.get(), "resumed-live")
            Screenshots.captureWhole(main.get(), "resumed-live")
            main.pause().stop().destroy()
            val list = Robolectric.buildActivity(SessionsActivity::class.java).setup()
            graph.settle()
            val banner = list.get().findViewById<TextView>(R.id.recording_banner_text).text.toString()
            assertTrue(banner, banner.contains(app.getString(R.string.record_resumed_short, gap)))
            Screenshots.captureScreen(list.get(), "resumed-sessions-banner")
            list.pause().stop().destroy()
        }
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        awaitEnded()
        assertFalse("nothing left to resume", offMainThread { inProgressFile().exists() })
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
        assertTrue(shadowOf(c.get()).isStoppedBySelf)
    }

    @Test
    fun `a recording the user stopped is not resumed, even when the process dies while it is being finished`() {
        val c = startService()
        for (i in 0 until 50) sendRound(1_000_000_000L + i * 5_000_000L)
        graph.pump()
        // Stop: forgotten on the recording's queue before the session is finished; then the process dies.
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.recordingDisk.runAll()
        assertFalse(offMainThread { inProgressFile().exists() })
        val count = sessions().size
        kill()
        val r = restart()
        graph.settle()
        assertEquals(RecordingState.Idle, state)
        assertTrue(shadowOf(r.get()).isStoppedBySelf)
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
        assertEquals(count, sessions().size)
        assertNull(format.metadata!!.continues)
    }

    @Test
    fun `a restart with no recording in progress stops at once`() {
        val r = restart()
        graph.settle()
        assertEquals(RecordingState.Idle, state)
        assertTrue(shadowOf(r.get()).isStoppedBySelf)
        assertTrue(sessions().isEmpty())
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    @GraphicsMode(GraphicsMode.Mode.NATIVE)
    fun `a restart Android refuses the foreground from 12 on waits for the user's tap, which continues it in a linked session with the gap to the tap`() {
        startService()
        for (i in 0 until 50) sendRound(1_000_000_000L + i * 5_000_000L)
        graph.pump()
        val before = (state as RecordingState.Active).session
        kill()
        graph.clock.elapsedNs += 10_000_000_000L
        // The system restarts the sticky service in the background. Android 12+ refuses it the foreground unless the
        // app is exempt (battery optimisation off, ...): Robolectric's ShadowService refuses only when told, so the test
        // tells it from 31 on, as the platform does; 8–11 allow it.
        val r = Robolectric.buildService(RecordingService::class.java, null).create()
        if (Build.VERSION.SDK_INT >= 31) {
            shadowOf(r.get()).setThrowInStartForeground(
                android.app.ForegroundServiceStartNotAllowedException("startForeground() not allowed due to mAllowStartForeground false"),
            )
        }
        assertEquals(Service.START_STICKY, r.get().onStartCommand(null, Service.START_FLAG_RETRY, 1))
        graph.settle()
        val nm = shadowOf(app.getSystemService(NotificationManager::class.java))
        if (Build.VERSION.SDK_INT < 31) {
            // Allowed: it resumes by itself, nothing to tap.
            val active = state as? RecordingState.Active ?: error("not resumed: $state")
            assertEquals(before.name, active.continues!!.previousSession)
            assertNull(nm.getNotification(RecordingService.INTERRUPTED_NOTIFICATION_ID))
            r.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
            awaitEnded()
            return
        }
        // Refused: nothing records, the wake lock is let go, the service stops; the recording waits for the user.
        assertEquals(RecordingState.Interrupted(before.name), state)
        assertTrue(shadowOf(r.get()).isStoppedBySelf)
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
        assertTrue(sensors.listeners.isEmpty())
        assertTrue("kept for the tap", offMainThread { inProgressFile().isFile })
        val n = nm.getNotification(RecordingService.INTERRUPTED_NOTIFICATION_ID) ?: error("no interrupted notification")
        assertEquals(app.getString(R.string.record_interrupted_title), n.extras.getCharSequence(Notification.EXTRA_TITLE).toString())
        assertEquals(app.getString(R.string.record_interrupted_text), n.extras.getCharSequence(Notification.EXTRA_TEXT).toString())
        // The tap starts the service in the foreground, which Android allows from a notification.
        val tap = shadowOf(n.contentIntent)
        assertTrue(tap.isForegroundService)
        assertEquals(RecordingService.ACTION_CONTINUE, tap.savedIntent.action)
        if (Build.VERSION.SDK_INT == Sdks.MAX) {
            // The app offers the same: Continue on the record bar.
            graph.graph.setNotificationsAnswered()
            val main = Robolectric.buildActivity(MainActivity::class.java).setup()
            shadowOf(Looper.getMainLooper()).idleFor(java.time.Duration.ofMillis(600))
            val toggle = main.get().findViewById<Button>(R.id.record_toggle)
            assertEquals(app.getString(R.string.record_continue), toggle.text.toString())
            assertEquals(app.getString(R.string.record_interrupted_bar), main.get().findViewById<TextView>(R.id.record_status).text.toString())
            Screenshots.assertLaidOut(main.get(), "interrupted-live")
            Screenshots.captureWhole(main.get(), "interrupted-live")
            toggle.performClick()
            assertEquals(RecordingService.ACTION_CONTINUE, shadowOf(app).nextStartedService.action)
            main.pause().stop().destroy()
        }
        // The user taps a minute later: the recording goes on in a new session that names the one before and the gap.
        val lastBefore = offMainThread { LineFormat.rows(before).last().split(',')[1].toLong() }
        graph.clock.elapsedNs += 60_000_000_000L
        val tappedAt = graph.clock.elapsedNs
        val c = Robolectric.buildService(RecordingService::class.java, tap.savedIntent).create().startCommand(0, 1)
        graph.settle()
        assertNotNull(shadowOf(c.get()).lastForegroundNotification)
        val active = state as? RecordingState.Active ?: error("not continued: $state")
        assertNotEquals(before, active.session)
        val continues = format.metadata!!.continues!!
        assertEquals(before.name, continues.previousSession)
        assertEquals(lastBefore, continues.gapStartElapsedRealtimeNs)
        assertEquals(tappedAt, continues.gapEndElapsedRealtimeNs)
        assertNull("the offer is gone", nm.getNotification(RecordingService.INTERRUPTED_NOTIFICATION_ID))
        for (i in 0 until 20) sendRound(80_000_000_000L + i * 5_000_000L)
        graph.pump()
        assertEquals(20L * SensorStreams.all.size, active.rows())
        c.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        awaitEnded()
        assertFalse("nothing left to resume", offMainThread { inProgressFile().exists() })
    }

    @Test
    fun `a restart refused for another reason (a permission missing) is told in the user's words, and the session before is kept for repair`() {
        startService()
        for (i in 0 until 50) sendRound(1_000_000_000L + i * 5_000_000L)
        graph.pump()
        val before = (state as RecordingState.Active).session
        kill()
        refusal = SecurityException("Starting FGS with type specialUse requires permissions")
        val r = restart()
        graph.settle()
        assertEquals(RecordingState.NotStarted(Foreground.Refusal.PERMISSION), state)
        assertTrue(shadowOf(r.get()).isStoppedBySelf)
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
        val text = shadowOf(app.getSystemService(NotificationManager::class.java)).getNotification(RecordingService.END_NOTIFICATION_ID)
            .extras.getCharSequence(Notification.EXTRA_TEXT).toString()
        assertEquals(app.getString(R.string.record_resume_failed, app.getString(R.string.foreground_refused_permission)), text)
        assertFalse("forgotten", offMainThread { inProgressFile().exists() })
        assertEquals(listOf(before), sessions())
        // The next listing repairs it as any interrupted session.
        assertTrue(offMainThread { graph.graph.sessions.interrupted() } == listOf(before))
    }

    @Test
    fun `disk work on the main thread fails`() {
        val e = runCatching { graph.graph.sessions.list() }.exceptionOrNull()
        assertTrue("$e", e is IllegalStateException && e.message == "disk work on the main thread")
    }

    private companion object {
        /** A long repair: a killed one-hour recording's stream files are read through to find their last whole rows (seconds). */
        const val REPAIR_OF_AN_HOUR_NS = 3_000_000_000L

        /** One frame at 60 Hz. */
        const val FRAME_NS = 16_666_667L
    }
}
