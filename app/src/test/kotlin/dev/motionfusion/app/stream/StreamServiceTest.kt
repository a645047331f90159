package dev.motionfusion.app.stream

import android.app.Notification
import android.content.Intent
import android.content.pm.ServiceInfo
import android.hardware.SensorManager
import android.net.wifi.WifiManager
import android.os.Build
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.platform.Foreground
import dev.motionfusion.app.platform.RenewedWakeLock
import dev.motionfusion.app.platform.Sdks
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.sensor.SensorStreams
import android.os.Looper
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.StreamClient
import java.net.URI
import java.time.Duration
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import org.junit.After
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNotNull
import org.junit.Assert.assertNotSame
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.android.controller.ServiceController
import org.robolectric.annotation.Config
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowPowerManager

/**
 * The live stream's foreground service: started by the controller, in the foreground with its type,
 * its wake lock and Wi-Fi locks per API level, its notification, its Stop; refused by the system; and
 * beside a recording, each holding the capture for itself.
 */
@RunWith(RobolectricTestRunner::class)
class StreamServiceTest {
    private val app = RuntimeEnvironment.getApplication()
    private var refusal: RuntimeException? = null
    private var graph = TestGraph(enterForeground = { service, id, n, type ->
        refusal?.let { throw it }
        androidx.core.app.ServiceCompat.startForeground(service, id, n, type)
    })
    private val controller get() = graph.graph.stream

    @After
    fun tearDown() {
        controller.stop()
        graph.settle()
    }

    /** Streaming on as the screen's switch turns it on; the service created from the intent the controller sent. */
    private fun startStreaming(): ServiceController<StreamService> {
        controller.start()
        val intent = shadowOf(app).nextStartedService
        assertEquals(StreamService::class.java.name, intent.component?.className)
        val c = Robolectric.buildService(StreamService::class.java, intent).create().startCommand(0, 1)
        graph.settle()
        return c
    }

    private fun text(n: Notification) = n.extras.getCharSequence(Notification.EXTRA_TEXT).toString()

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `streaming runs in the foreground as connectedDevice with a wake lock and the level's Wi-Fi locks, and Stop in the notification ends it`() {
        val c = startStreaming()
        val service = shadowOf(c.get())
        val on = controller.state.value as StreamState.On
        // Types exist from API 29 and are required from 34: below 34 the service starts without one.
        if (Build.VERSION.SDK_INT >= 29) {
            val expected = if (Build.VERSION.SDK_INT >= 34) ServiceInfo.FOREGROUND_SERVICE_TYPE_CONNECTED_DEVICE else 0
            assertEquals(expected, c.get().foregroundServiceType)
        }
        val nm = app.getSystemService(android.app.NotificationManager::class.java)
        assertEquals(android.app.NotificationManager.IMPORTANCE_LOW, nm.getNotificationChannel(Foreground.CHANNEL_STREAMING).importance)
        assertEquals(Foreground.CHANNEL_STREAMING, service.lastForegroundNotification.channelId)
        val shown = shadowOf(nm).getNotification(StreamService.NOTIFICATION_ID)
        assertEquals("Waiting for a client · code ${on.code}", text(shown))
        assertEquals("Stop", shown.actions.single().title.toString())
        // On the lock screen the public version is shown: the title, not the pairing code.
        assertEquals(Notification.VISIBILITY_PRIVATE, shown.visibility)
        val public = shown.publicVersion
        assertTrue("a public version", public != null)
        assertFalse(on.code in public!!.extras.getCharSequence(Notification.EXTRA_TEXT)?.toString().orEmpty())
        assertFalse(on.code in public.extras.getCharSequence(Notification.EXTRA_TITLE)?.toString().orEmpty())
        val lock = ShadowPowerManager.getLatestWakeLock()
        assertTrue("partial wake lock held", lock.isHeld)
        val modes = graph.wifiLocks.held.toList()
        assertEquals(StreamService.wifiLockModes(Build.VERSION.SDK_INT), modes)
        // Below 34 the high-performance lock is what keeps Wi-Fi awake with the screen off; from 34 it is low latency.
        @Suppress("DEPRECATION")
        assertEquals(Build.VERSION.SDK_INT < 34, WifiManager.WIFI_MODE_FULL_HIGH_PERF in modes)

        // The notification's Stop: the controller stops, then the service ends with its locks.
        c.get().onStartCommand(Intent(app, StreamService::class.java).setAction(StreamService.ACTION_STOP), 0, 2)
        shadowOf(Looper.getMainLooper()).idle()
        assertEquals(StreamState.Stopping, controller.state.value)
        assertEquals("Closing the connections…", text(shadowOf(nm).getNotification(StreamService.NOTIFICATION_ID)))
        assertTrue("still in the foreground while the connections close", lock.isHeld)
        graph.settle()
        assertEquals(StreamState.Off, controller.state.value)
        assertFalse("wake lock released", lock.isHeld)
        assertEquals(emptyList<Int>(), graph.wifiLocks.held.toList())
        assertTrue(service.isForegroundStopped)
        assertTrue(service.isStoppedBySelf)
    }

    @Test
    fun `a laptop that asks to connect is in the notification with Deny and Allow, immutable, and Allow there pairs it`() {
        val c = startStreaming()
        val on = controller.state.value as StreamState.On
        val nm = shadowOf(app.getSystemService(android.app.NotificationManager::class.java))
        val client = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code, client = "fusion listen on lab")) {}
        val pool = java.util.concurrent.Executors.newSingleThreadExecutor()
        try {
            val hello = pool.submit<StreamMessage.Hello> { client.connect() }
            var shown = nm.getNotification(StreamService.NOTIFICATION_ID)
            for (k in 0 until 10_000) {
                shadowOf(Looper.getMainLooper()).idle()
                shown = nm.getNotification(StreamService.NOTIFICATION_ID)
                if (shown.actions.size > 1) break
                java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
            }
            assertEquals("“fusion listen on lab” at 127.0.0.1 asks to connect", text(shown))
            assertEquals(listOf("Deny", "Allow", "Stop"), shown.actions.map { it.title.toString() })
            for (action in shown.actions) assertTrue(shadowOf(action.actionIntent).isImmutable)
            // On the lock screen: the title alone, neither the name nor the address.
            assertFalse("127.0.0.1" in shown.publicVersion.extras.getCharSequence(Notification.EXTRA_TEXT)?.toString().orEmpty())
            val allow = shadowOf(shown.actions[1].actionIntent).savedIntent
            assertEquals(StreamService.ACTION_ALLOW, allow.action)
            c.get().onStartCommand(allow, 0, 2)
            graph.settle()
            hello.get(10, TimeUnit.SECONDS)
            for (k in 0 until 10_000) {
                shadowOf(Looper.getMainLooper()).idle()
                if (text(nm.getNotification(StreamService.NOTIFICATION_ID)).startsWith("1 client")) break
                java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
            }
            val paired = nm.getNotification(StreamService.NOTIFICATION_ID)
            assertEquals("1 client · code ${on.code}", text(paired))
            assertEquals(listOf("Stop"), paired.actions.map { it.title.toString() })
        } finally {
            pool.shutdownNow()
            client.close()
        }
    }

    @Test
    fun `the wake lock is renewed every minute of the injected clock while waiting for a client, when nothing else changes`() {
        val c = startStreaming()
        val lock = ShadowPowerManager.getLatestWakeLock()
        val held = shadowOf(lock).timesHeld
        val main = shadowOf(Looper.getMainLooper())
        main.idleFor(Duration.ofMillis(StreamService.RENEW_TICK_MS))
        assertEquals("not renewed before a minute", held, shadowOf(lock).timesHeld)
        for (k in 1..3) {
            graph.clock.elapsedNs += RenewedWakeLock.RENEW_NS
            main.idleFor(Duration.ofMillis(StreamService.RENEW_TICK_MS))
            assertEquals("renewed $k times, with no client and no change of state", held + k, shadowOf(lock).timesHeld)
        }
        assertTrue(controller.state.value is StreamState.On)
        controller.stop()
        graph.settle()
        assertFalse(lock.isHeld)
        assertTrue(shadowOf(c.get()).isStoppedBySelf)
    }

    @Test
    fun `the notification counts the paired clients, is posted again only when its text changes, and ends with streaming`() {
        // A gyroscope, so that the stream offers its samples: a graph that sees it.
        shadowOf(app.getSystemService(SensorManager::class.java)).addSensor(SensorBuilder.newBuilder().setType(android.hardware.Sensor.TYPE_GYROSCOPE).build())
        graph = TestGraph()
        val c = startStreaming()
        val nm = shadowOf(app.getSystemService(android.app.NotificationManager::class.java))
        val on = controller.state.value as StreamState.On
        val got = CountDownLatch(200)
        val client = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code)) { if (it is StreamMessage.Sample) got.countDown() }
        try {
            graph.connectAllowed(client) // returns with the hello: the server lists the client as paired
            shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1)) // the state's refresh
            assertEquals("1 client · code ${on.code}", text(nm.getNotification(StreamService.NOTIFICATION_ID)))
            val updates = c.get().notificationUpdates
            val v = floatArrayOf(0.01f, -0.02f, 0.003f)
            for (i in 0 until 200) graph.capture.ring.offer(SessionStream.GYROSCOPE, 1_000_000_000L + i * 5_000_000L, 3, v, 3)
            graph.pump()
            assertTrue("the client got the samples", got.await(10, TimeUnit.SECONDS))
            // Refreshed with the client's new counts: the state changes, the notification's text does not.
            repeat(3) { shadowOf(Looper.getMainLooper()).idleFor(Duration.ofSeconds(1)) }
            val client1 = (controller.state.value as StreamState.On).clients.single()
            assertTrue("$client1", client1.sent >= 200)
            assertEquals(updates, c.get().notificationUpdates)
        } finally {
            client.close()
        }
        // Turned off on the screen: the service ends itself with its locks.
        controller.stop()
        graph.settle()
        assertTrue(shadowOf(c.get()).isStoppedBySelf)
        assertFalse(ShadowPowerManager.getLatestWakeLock().isHeld)
    }

    @Test
    fun `a foreground start the system refuses stops the stream and says why`() {
        refusal = IllegalStateException("startForeground() not allowed")
        val c = startStreaming()
        // In the user's words, not the system's (the system's go to the log).
        assertEquals(StreamState.Failed(dev.motionfusion.app.R.string.foreground_refused_background), controller.state.value)
        assertTrue(shadowOf(c.get()).isStoppedBySelf)
        assertEquals(emptyList<Int>(), graph.wifiLocks.held.toList())
        assertFalse(graph.capture.isRunning)
    }

    @Test
    fun `recording and streaming together, each holding the capture, and stopping the stream leaves the recording whole`() {
        val sensors = shadowOf(app.getSystemService(SensorManager::class.java))
        val all = SensorStreams.all.associateWith { s ->
            SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}").build().also(sensors::addSensor)
        }
        // Sensors were added after the graph was made: a graph that sees them.
        val graph = TestGraph()
        val rec = Robolectric.buildService(RecordingService::class.java, Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_START))
            .create().startCommand(0, 1)
        graph.settle()
        val recordingLock = ShadowPowerManager.getLatestWakeLock()
        assertTrue(graph.graph.recordings.isRecording)

        graph.graph.stream.start()
        val stream = Robolectric.buildService(StreamService::class.java, shadowOf(app).nextStartedService).create().startCommand(0, 1)
        graph.settle()
        val streamLock = ShadowPowerManager.getLatestWakeLock()
        assertNotSame(recordingLock, streamLock)
        assertTrue(graph.graph.stream.state.value is StreamState.On)

        fun send(t: Long) = all.forEach { (s, sensor) ->
            sensors.sendSensorEventToListeners(
                SensorEventBuilder.newBuilder().setSensor(sensor).setValues(FloatArray(s.valueCount) { 0.1f * it }).setTimestamp(t).build(),
            )
        }
        for (i in 0 until 50) send(1_000_000_000L + i * 5_000_000L)
        graph.pump()
        val rowsBefore = (graph.graph.recordings.state.value as RecordingState.Active).rows()
        assertTrue("$rowsBefore rows", rowsBefore >= 50L * all.size)

        graph.graph.stream.stop()
        graph.settle()
        assertTrue(shadowOf(stream.get()).isStoppedBySelf)
        assertFalse(streamLock.isHeld)
        // The recording goes on: its lock, its capture, its rows.
        assertTrue(recordingLock.isHeld)
        assertTrue(graph.capture.isRunning)
        assertNotNull(sensors.listeners.singleOrNull())
        for (i in 50 until 100) send(1_000_000_000L + i * 5_000_000L)
        graph.pump()
        val rowsAfter = (graph.graph.recordings.state.value as RecordingState.Active).rows()
        assertTrue("$rowsBefore → $rowsAfter rows", rowsAfter >= rowsBefore + 50L * all.size)

        rec.get().onStartCommand(Intent(app, RecordingService::class.java).setAction(RecordingService.ACTION_STOP), 0, 2)
        graph.pump()
        graph.settle()
        assertTrue(graph.graph.recordings.state.value is RecordingState.Ended)
        assertFalse(graph.capture.isRunning)
        assertTrue(sensors.listeners.isEmpty())
    }

    @Test
    fun `the Wi-Fi locks by level`() {
        @Suppress("DEPRECATION")
        val highPerf = WifiManager.WIFI_MODE_FULL_HIGH_PERF
        val lowLatency = WifiManager.WIFI_MODE_FULL_LOW_LATENCY
        for (sdk in Sdks.MIN..Sdks.MAX) {
            val modes = StreamService.wifiLockModes(sdk)
            assertEquals("$sdk", sdk < 34, highPerf in modes)
            assertEquals("$sdk", sdk >= 29, lowLatency in modes)
        }
    }
}
