package dev.motionfusion.app.stream

import android.content.Intent
import android.hardware.Sensor
import android.hardware.SensorManager
import android.os.Looper
import dev.motionfusion.app.TestGraph
import dev.motionfusion.app.record.RecordingService
import dev.motionfusion.app.record.RecordingState
import dev.motionfusion.app.sensor.SensorStreams
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.RemoteStart
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.StreamClient
import dev.motionfusion.stream.StreamEnd
import dev.motionfusion.stream.StreamServer
import java.net.URI
import java.util.concurrent.LinkedBlockingQueue
import java.util.concurrent.TimeUnit
import org.junit.After
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertNotNull
import org.junit.Assert.assertNull
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.Robolectric
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import dev.motionfusion.app.platform.Sdks
import org.robolectric.shadows.SensorBuilder
import org.robolectric.shadows.SensorEventBuilder

/**
 * A laptop starts a recording through the app's stream server (docs/STREAMING.md, "Remote control"), service level: the
 * `control` start reaches the recording service as the intent the app sends (the service started as Record starts it),
 * the session notes `remote_start` and keeps no sample before the laptop's instant; with the Stream screen's switch off
 * the command is refused and the link closed (4013, its reason), and no recording starts. The phone's clock is the
 * graph's injected clock.
 */
@RunWith(RobolectricTestRunner::class)
class RemoteStartServiceTest {
    private val app = RuntimeEnvironment.getApplication()
    private val sensors = shadowOf(app.getSystemService(SensorManager::class.java))
    private val all: Map<SessionStream, Sensor> = SensorStreams.all.associateWith { s ->
        SensorBuilder.newBuilder().setType(s.androidType).setName("Test ${s.name}").build().also(sensors::addSensor)
    }

    // The app's wiring of a laptop's start and stop (AppGraph.create): RecordingService's entry points.
    private val graph = TestGraph(
        remoteRecordStart = { start -> RecordingService.startRemote(app, start)?.let { app.getString(it.text) } },
        remoteRecordStop = { RecordingService.stop(app) },
    )
    private val controller get() = graph.graph.stream
    private val closing = ArrayList<AutoCloseable>()

    @After
    fun tearDown() {
        closing.forEach { runCatching { it.close() } }
        controller.stop()
        graph.settle()
    }

    /** Streaming on as the screen's switch turns it on; the stream service created from the intent the controller sent. */
    private fun startStreaming(): StreamState.On {
        controller.start()
        val intent = shadowOf(app).nextStartedService
        assertEquals(StreamService::class.java.name, intent.component?.className)
        Robolectric.buildService(StreamService::class.java, intent).create().startCommand(0, 1)
        graph.settle()
        return controller.state.value as StreamState.On
    }

    /** A laptop paired on loopback (the user allowed it on the phone); what the phone sends it goes into [results]. */
    private fun laptop(on: StreamState.On, results: LinkedBlockingQueue<StreamMessage>): StreamClient {
        val client = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code, emptyList(), client = "fusion record on lab")) { results += it }
        closing += client
        graph.connectAllowed(client)
        return client
    }

    /** The phone's answer to a command (other messages skipped), within 10 s of the server's threads. */
    private fun answer(results: LinkedBlockingQueue<StreamMessage>): StreamMessage.ControlResult {
        while (true) {
            shadowOf(Looper.getMainLooper()).idle()
            val m = results.poll(10, TimeUnit.SECONDS) ?: error("no answer from the phone")
            if (m is StreamMessage.ControlResult) return m
        }
    }

    /** The next service the app started, if it is the recording service. */
    private fun recordingIntent(): Intent? {
        while (true) {
            val i = shadowOf(app).nextStartedService ?: return null
            if (i.component?.className == RecordingService::class.java.name) return i
        }
    }

    private fun send(t: Long) = all.forEach { (s, sensor) ->
        sensors.sendSensorEventToListeners(
            SensorEventBuilder.newBuilder().setSensor(sensor).setValues(FloatArray(s.valueCount) { 0.1f * (it + 1) }).setTimestamp(t)
                .setAccuracy(SensorManager.SENSOR_STATUS_ACCURACY_HIGH).build(),
        )
    }

    @Test
    @Config(minSdk = Sdks.MIN, maxSdk = Sdks.MAX)
    fun `a laptop's start while remote control is allowed starts the recording service as Record does, tagged, with no sample before its instant`() {
        val on = startStreaming()
        controller.allowRemoteControl(true)
        val results = LinkedBlockingQueue<StreamMessage>()
        val laptop = laptop(on, results)
        // The laptop's instant, half a second ahead of the phone's (injected) sensor clock.
        val atNs = graph.clock.elapsedNs + 500_000_000L
        assertTrue(laptop.send(StreamMessage.Control(1, StreamMessage.Control.Command.START, 9_000_000_000L, atNs, "lab boot 1")))
        val result = answer(results)
        assertTrue("${result.reason}", result.ok)

        // What the system does with the app's start: the service created from its intent, in the foreground as for Record.
        val intent = recordingIntent() ?: error("the recording service was not started")
        assertEquals(RecordingService.ACTION_START, intent.action)
        val service = Robolectric.buildService(RecordingService::class.java, intent).create().startCommand(0, 1)
        graph.settle()
        assertNotNull(shadowOf(service.get()).lastForegroundNotification)
        assertTrue(graph.graph.recordings.state.value is RecordingState.Active)

        // 100 rounds 5 ms apart, half before the instant: those are not kept.
        for (i in -50 until 50) send(atNs + i * 5_000_000L)
        graph.pump()
        // The laptop's stop, delivered to the running service as the system would.
        assertTrue(laptop.send(StreamMessage.Control(2, StreamMessage.Control.Command.STOP, 9_900_000_000L)))
        assertTrue(answer(results).ok)
        val stop = recordingIntent() ?: error("no stop")
        assertEquals(RecordingService.ACTION_STOP, stop.action)
        service.get().onStartCommand(stop, 0, 2)
        graph.pump()
        graph.settle()
        val ended = graph.graph.recordings.state.value as? RecordingState.Ended ?: error("not ended: ${graph.graph.recordings.state.value}")
        val session = ended.session ?: error("no session")
        dev.motionfusion.app.offMainThread {
            SessionReader.open(session.toPath()).use { s ->
                assertEquals(RemoteStart("fusion record on lab", "lab boot 1", 9_000_000_000L, atNs), s.metadata.remoteStart)
                for (stream in listOf(SessionStream.GYROSCOPE, SessionStream.ACCELEROMETER, SessionStream.MAGNETOMETER)) {
                    val times = s.events(setOf(stream)).use { e -> val t = ArrayList<Long>(); while (e.next()) t += e.timestampNs; t }
                    assertEquals("$stream", atNs, times.first())
                    assertEquals("$stream", 50, times.size)
                }
            }
        }
    }

    @Test
    fun `with remote control not allowed a laptop's start is refused, the link closed with the reason, and nothing recorded`() {
        val on = startStreaming()
        assertFalse("off by default", controller.remoteControlAllowed)
        val results = LinkedBlockingQueue<StreamMessage>()
        val laptop = laptop(on, results)
        assertTrue(laptop.send(StreamMessage.Control(1, StreamMessage.Control.Command.START, 9_000_000_000L, graph.clock.elapsedNs, "lab boot 1")))
        val refused = answer(results)
        assertFalse(refused.ok)
        assertEquals(StreamServer.REMOTE_CONTROL_OFF, refused.reason)
        assertTrue(laptop.awaitClose(10_000))
        // Closed by the phone with 4013 (CLOSE_NO_REMOTE_CONTROL) and the same reason.
        assertEquals(StreamEnd.REFUSED, laptop.end)
        assertTrue("${laptop.endReason}", laptop.endReason!!.endsWith(StreamServer.REMOTE_CONTROL_OFF))
        graph.settle()
        assertNull("no recording service started", recordingIntent())
        assertFalse(graph.graph.recordings.isRecording)
        assertNull((controller.state.value as StreamState.On).controlledBy)
    }
}
