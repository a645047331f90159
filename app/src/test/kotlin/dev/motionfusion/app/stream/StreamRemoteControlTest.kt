package dev.motionfusion.app.stream

import dev.motionfusion.app.live.TestCapture
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.RemoteStart
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.core.sync.ClockExchange
import dev.motionfusion.stream.ClockPinger
import dev.motionfusion.stream.StreamClient
import dev.motionfusion.stream.StreamEnd
import dev.motionfusion.stream.StreamServer
import java.net.URI
import java.security.SecureRandom
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.Executor
import java.util.concurrent.LinkedBlockingQueue
import java.util.concurrent.TimeUnit
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.cancel
import kotlinx.coroutines.flow.first
import kotlinx.coroutines.runBlocking
import kotlinx.coroutines.withTimeoutOrNull
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * A laptop in control of the phone's recordings through the controller's real server on loopback (docs/STREAMING.md,
 * "Remote control"): refused while the switch is off, carried out by the recording once on, the laptop shown; the link's
 * clock exchanges handed to the recording with the laptop clock they name.
 */
class StreamRemoteControlTest {
    private val scope = CoroutineScope(SupervisorJob() + Dispatchers.Unconfined)
    private val metadata = SessionMetadata(source = "Motion Fusion 0.1.0", startAnchor = ClockAnchor(1_764_000_000_000, 5_000_000_000))
    private val c = TestCapture()

    /** The recording service as the controller sees it: what it was asked. */
    private class FakeRecording : RemoteRecording {
        val starts = ConcurrentLinkedQueue<RemoteStart>()
        val marks = ConcurrentLinkedQueue<Pair<Long, String>>()
        val exchanges = LinkedBlockingQueue<Pair<ClockExchange, String>>()
        @Volatile var recording = false
        override fun start(start: RemoteStart): String? = if (recording) "already recording" else { starts += start; recording = true; null }
        override fun stop(): String? = if (!recording) "not recording" else { recording = false; null }
        override fun mark(atNs: Long, label: String): String? = if (!recording) "not recording" else { marks += atNs to label; null }
        override fun clockExchange(e: ClockExchange, laptopClock: String) { exchanges += e to laptopClock }
    }

    private val recording = FakeRecording()
    private val controller = StreamController(
        c.capture, { metadata }, scope, port = 0, addresses = { listOf("192.168.1.23") }, random = SecureRandom(), control = Executor { it.run() },
        lookup = Executor { it.run() }, recording = recording, sensorClock = { 77_000_000_000L },
    )
    private val closing = ArrayList<AutoCloseable>()

    @AfterEach
    fun end() {
        closing.forEach { runCatching { it.close() } }
        controller.stop()
        scope.cancel()
    }

    /** A paired client; [ask]: the address is new, the user allows it (an address allowed once is not asked again). */
    private fun client(on: StreamState.On, results: LinkedBlockingQueue<StreamMessage>, ask: Boolean = true): StreamClient {
        val client = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code, emptyList(), client = "fusion record on lab")) { results += it }
        closing += client
        if (!ask) {
            client.connect()
            return client
        }
        val pool = java.util.concurrent.Executors.newSingleThreadExecutor()
        try {
            val hello = pool.submit<StreamMessage.Hello> { client.connect() }
            val asking = runBlocking { withTimeoutOrNull(10_000) { controller.state.first { it is StreamState.On && it.clients.any { c -> c.awaitingConfirmation } } } }
                as? StreamState.On ?: error("nobody asks")
            controller.allow(asking.clients.first { it.awaitingConfirmation }.id)
            hello.get(10, TimeUnit.SECONDS)
        } finally {
            pool.shutdown()
        }
        return client
    }

    private fun answer(results: LinkedBlockingQueue<StreamMessage>): StreamMessage.ControlResult {
        while (true) {
            val m = results.poll(10, TimeUnit.SECONDS) ?: error("no answer")
            if (m is StreamMessage.ControlResult) return m
        }
    }

    @Test
    fun `off by default a command is refused and the link closed, on it starts, marks and stops the recording and the screen says who`() {
        assertFalse(controller.remoteControlAllowed, "off by default")
        controller.start()
        val on = controller.state.value as StreamState.On
        val results = LinkedBlockingQueue<StreamMessage>()
        val refused = client(on, results)
        assertTrue(refused.send(StreamMessage.Control(1, StreamMessage.Control.Command.START, 5, 6, "lab boot 1")))
        val no = answer(results)
        assertFalse(no.ok)
        assertEquals(StreamServer.REMOTE_CONTROL_OFF, no.reason)
        assertTrue(refused.awaitClose(10_000))
        assertEquals(StreamEnd.REFUSED, refused.end)
        assertTrue(recording.starts.isEmpty())

        controller.allowRemoteControl(true)
        val laptop = client(on, results, ask = false)
        assertTrue(laptop.send(StreamMessage.Control(2, StreamMessage.Control.Command.START, 9_000_000_000, 80_000_000_000, "lab boot 1")))
        assertTrue(answer(results).ok)
        assertEquals(RemoteStart("fusion record on lab", "lab boot 1", 9_000_000_000, 80_000_000_000), recording.starts.single())
        val shown = runBlocking { withTimeoutOrNull(10_000) { controller.state.first { (it as? StreamState.On)?.controlledBy != null } } } as StreamState.On
        assertEquals("fusion record on lab (127.0.0.1)", shown.controlledBy)
        // A second start while recording: refused with the reason, the link stays.
        assertTrue(laptop.send(StreamMessage.Control(3, StreamMessage.Control.Command.START, 1, 2)))
        assertEquals(StreamMessage.ControlResult(3, false, "already recording"), answer(results))
        // A mark without an instant: at its receipt on the sensor clock.
        assertTrue(laptop.send(StreamMessage.Control(4, StreamMessage.Control.Command.MARK, 1, label = "jump")))
        assertTrue(answer(results).ok)
        assertEquals(77_000_000_000L to "jump", recording.marks.single())
        assertTrue(laptop.send(StreamMessage.Control(5, StreamMessage.Control.Command.STOP, 1)))
        assertTrue(answer(results).ok)
        assertFalse(recording.recording)

        // The link's clock exchanges reach the recording, with the laptop clock the pings name.
        val pinger = ClockPinger(System::nanoTime, {}, "lab boot 1")
        // The phone answers one ping per 10 ms of its clock: pinged until two whole exchanges reached the recording (bounded).
        val got = ArrayList<Pair<ClockExchange, String>>()
        var pings = 0
        while (got.size < 2) {
            check(++pings < 5_000) { "fewer than two exchanges" }
            assertTrue(laptop.send(pinger.ping()))
            (results.poll(20, TimeUnit.MILLISECONDS) as? StreamMessage.Pong)?.let { pinger.pong(it) }
            recording.exchanges.poll()?.let { got += it }
        }
        assertTrue(got.all { it.second == "lab boot 1" && it.first.t2 == 77_000_000_000L }, got.toString())

        // Turned off: refused again, and nobody shown in control.
        controller.allowRemoteControl(false)
        assertNull((controller.state.value as StreamState.On).controlledBy)
        assertTrue(laptop.send(StreamMessage.Control(6, StreamMessage.Control.Command.STOP, 1)))
        assertFalse(answer(results).ok)
    }
}
