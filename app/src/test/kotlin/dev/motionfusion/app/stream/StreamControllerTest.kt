package dev.motionfusion.app.stream

import dev.motionfusion.app.R
import dev.motionfusion.app.live.TestCapture
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.StreamClient
import java.net.URI
import dev.motionfusion.core.stream.StreamCodec
import java.net.DatagramPacket
import java.net.DatagramSocket
import java.net.InetAddress
import java.net.InetSocketAddress
import java.net.ServerSocket
import java.security.SecureRandom
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executor
import java.util.concurrent.TimeUnit
import java.util.concurrent.ConcurrentLinkedQueue
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
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test

/**
 * The app's side of the live stream on the JVM: the controller's real server on loopback, a real
 * [StreamClient] paired with the code it shows, and events fed through the one capture path. The
 * server's start and stop run on the controller's control executor: here either at once on the
 * caller's thread, or queued until the test runs them ([Queued]).
 */
class StreamControllerTest {
    /** The test thread plays the main thread: the controller's steps come back to it at once. */
    private val scope = CoroutineScope(SupervisorJob() + Dispatchers.Unconfined)
    private val metadata = SessionMetadata(appVersion = "0.1.0", source = "Motion Fusion 0.1.0", startAnchor = ClockAnchor(1_764_000_000_000, 5_000_000_000))
    private val c = TestCapture()
    private val controller = StreamController(
        c.capture, { metadata }, scope, port = 0, addresses = { listOf("192.168.1.23") }, random = SecureRandom(), control = Executor { it.run() },
        lookup = Executor { it.run() },
    )

    /** A control executor whose tasks wait until the test runs them. */
    private class Queued : Executor {
        private val tasks = ArrayDeque<Runnable>()
        val pending: Int get() = tasks.size
        override fun execute(command: Runnable) {
            tasks.addLast(command)
        }

        fun runAll() {
            while (tasks.isNotEmpty()) tasks.removeFirst().run()
        }
    }

    private val queued = Queued()
    private var refusal: Int? = null
    /** The UDP push's lookups of [held], apart from its control tasks. */
    private val lookups = Queued()
    private val held = StreamController(
        c.capture, { metadata }, scope, port = 0, addresses = { listOf("192.168.1.23") }, control = queued, keepAlive = { refusal }, lookup = lookups,
    )

    @AfterEach
    fun end() {
        controller.stop()
        held.stop()
        queued.runAll()
        lookups.runAll()
        queued.runAll()
        scope.cancel()
    }

    /** Waits for the controller's state to say [what] (it is refreshed about once a second); fails after 10 s. */
    private fun awaitState(what: String, done: (StreamState) -> Boolean) {
        runBlocking { withTimeoutOrNull(10_000) { controller.state.first(done) } } ?: error("timed out waiting for $what")
    }

    @Test
    fun `turned on, a paired client gets every raw event and the orientation of every filter step, and off undoes all`() {
        assertEquals(StreamState.Off, controller.state.value)
        controller.start()
        val on = controller.state.value as StreamState.On
        assertTrue(on.code.matches(Regex("[0-9]{6}")), on.code)
        assertEquals(listOf("192.168.1.23"), on.addresses)
        assertTrue(on.port > 0)

        val received = ConcurrentLinkedQueue<StreamMessage>()
        val rounds = 200
        // Every sample, and the orientation of the last gyroscope reading (orientations come in order, so all before it too).
        val samplesDue = CountDownLatch(rounds * 3)
        val lastOrientation = CountDownLatch(1)
        val lastGyroNs = 1_000_000_000L + (rounds - 1) * 5_000_000L + 2_000_000
        val client = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code)) {
            received += it
            if (it is StreamMessage.Sample) samplesDue.countDown()
            if (it is StreamMessage.Orientation && it.timestampNs == lastGyroNs) lastOrientation.countDown()
        }
        try {
            val hello = connectAllowed(client)
            assertEquals(metadata, hello.metadata)
            assertTrue(SessionStream.ORIENTATION in hello.streams && SessionStream.GYROSCOPE in hello.streams, hello.streams.toString())
            awaitState("the client listed as paired") { it is StreamState.On && it.clients.any { c -> c.paired } }

            for (i in 0 until rounds) {
                val t = 1_000_000_000L + i * 5_000_000L
                c.offer(SessionStream.ACCELEROMETER, t, 0.1f, 0.2f, 9.81f, accuracy = 3)
                c.offer(SessionStream.MAGNETOMETER, t + 1_000_000, 20f, 0f, -40f, accuracy = 2)
                c.offer(SessionStream.GYROSCOPE, t + 2_000_000, 0.01f * i, -0.02f, 0.003f, accuracy = 3)
            }
            c.drain()
            c.nowNs += 1_000_000_000L
            c.drain()

            assertTrue(samplesDue.await(10, TimeUnit.SECONDS) && lastOrientation.await(10, TimeUnit.SECONDS), "every sample and orientation")
            val samples = received.filterIsInstance<StreamMessage.Sample>()
            assertEquals(rounds * 3, samples.size)
            val gyro = samples.filter { it.stream == SessionStream.GYROSCOPE }
            assertEquals(rounds, gyro.size)
            assertEquals(StreamMessage.Sample(SessionStream.GYROSCOPE, 1_000_000_000L + 7 * 5_000_000L + 2_000_000, floatArrayOf(0.07f, -0.02f, 0.003f), 3), gyro[7])
            assertEquals(StreamMessage.Sample(SessionStream.MAGNETOMETER, 1_001_000_000L, floatArrayOf(20f, 0f, -40f), 2), samples.first { it.stream == SessionStream.MAGNETOMETER })
            val orientations = received.filterIsInstance<StreamMessage.Orientation>()
            // One per gyroscope step once the filter is initialised, at the gyroscope's times, each a unit quaternion.
            assertTrue(orientations.size in rounds - 1..rounds, "${orientations.size} orientations")
            assertEquals(gyro.last().timestampNs, orientations.last().timestampNs)
            for (o in orientations) assertEquals(1.0, o.qw * o.qw + o.qx * o.qx + o.qy * o.qy + o.qz * o.qz, 1e-9)
        } finally {
            client.close()
        }

        controller.stop()
        assertEquals(StreamState.Off, controller.state.value)
        assertFalse(controller.isOn)
        // The test's own hold remains: the controller released its own.
        assertTrue(c.capture.isRunning)
        // Capture goes on with nothing listening.
        c.offer(SessionStream.GYROSCOPE, 3_000_000_000L, 0f, 0f, 0f)
        c.drain()
        c.capture.release()
        assertFalse(c.capture.isRunning)
    }

    /** Waits until the controller shows a laptop asking to connect; fails after 10 s. */
    private fun awaitAsking(): dev.motionfusion.stream.StreamClientInfo = runBlocking {
        withTimeoutOrNull(10_000) { controller.state.first { it is StreamState.On && it.clients.any { c -> c.awaitingConfirmation } } }
    }.let { it as? StreamState.On ?: error("nobody asks: ${controller.state.value}") }.clients.first { it.awaitingConfirmation }

    /** Connects [client] on a thread of its own and, once the controller shows it asking, allows it; returns its hello. */
    private fun connectAllowed(client: StreamClient): StreamMessage.Hello {
        val pool = java.util.concurrent.Executors.newSingleThreadExecutor()
        try {
            val hello = pool.submit<StreamMessage.Hello> { client.connect() }
            controller.allow(awaitAsking().id)
            return hello.get(10, TimeUnit.SECONDS)
        } finally {
            pool.shutdown()
        }
    }

    @Test
    fun `a laptop with the right code waits for the user, denied it is closed and a new code shown, allowed it pairs and is not asked again`() {
        controller.start()
        val on = controller.state.value as StreamState.On
        val url = URI("ws://127.0.0.1:${on.port}")
        val denied = StreamClient(url, StreamMessage.Pair(on.code, client = "fusion listen on lab")) {}
        val pool = java.util.concurrent.Executors.newSingleThreadExecutor()
        try {
            val refused = pool.submit<Throwable?> { runCatching { denied.connect() }.exceptionOrNull() }
            val asking = awaitAsking()
            assertEquals("fusion listen on lab", asking.name)
            assertEquals("127.0.0.1", asking.address)
            assertFalse(asking.paired)
            controller.deny(asking.id)
            val e = refused.get(10, TimeUnit.SECONDS)
            assertTrue(e?.message?.contains("denied on the phone") == true, e?.message)
            assertEquals(dev.motionfusion.stream.StreamEnd.DENIED, denied.end)
            // Whoever asked knew the code: a new one is shown.
            awaitState("a new code") { it is StreamState.On && it.code != on.code && it.clients.none { c -> c.awaitingConfirmation } }
            val code = (controller.state.value as StreamState.On).code
            StreamClient(url, StreamMessage.Pair(on.code)) {}.use { old ->
                assertTrue(runCatching { old.connect() }.exceptionOrNull()?.message?.contains("pairing code wrong") == true)
            }
            StreamClient(url, StreamMessage.Pair(code)) {}.use { allowed ->
                connectAllowed(allowed)
                awaitState("the allowed client paired") { it is StreamState.On && it.clients.any { c -> c.paired } }
                // The same address again (the laptop reconnecting): paired without asking.
                StreamClient(url, StreamMessage.Pair(code)) {}.use { again -> again.connect(5_000) }
            }
        } finally {
            pool.shutdownNow()
            denied.close()
        }
    }

    @Test
    fun `after five wrong codes, from any address, the server makes a new code and it is shown`() {
        controller.start()
        val first = (controller.state.value as StreamState.On)
        val wrong = if (first.code == "000000") "000001" else "000000"
        repeat(5) {
            val client = StreamClient(URI("ws://127.0.0.1:${first.port}"), StreamMessage.Pair(wrong)) {}
            runCatching { client.connect() }
            client.close()
        }
        awaitState("a new code") { it is StreamState.On && it.code != first.code }
    }

    @Test
    fun `a server that dies while on is shown as failed, not on`() {
        var boom = false
        val dying = StreamController(
            c.capture, { if (boom) throw OutOfMemoryError("simulated") else metadata }, scope, port = 0, addresses = { emptyList() },
            control = Executor { it.run() }, lookup = Executor { it.run() },
        )
        try {
            dying.start()
            val on = dying.state.value as StreamState.On
            boom = true
            // Pairing asks for the metadata: what a server out of memory meets there ends it.
            val client = StreamClient(URI("ws://127.0.0.1:${on.port}"), StreamMessage.Pair(on.code)) {}
            runCatching { client.connect(5_000) }
            client.close()
            runBlocking { withTimeoutOrNull(10_000) { dying.state.first { it is StreamState.Failed } } } ?: error("not shown as failed: ${dying.state.value}")
            assertEquals(StreamState.Failed(R.string.stream_failure_server_stopped), dying.state.value)
        } finally {
            dying.stop()
        }
    }

    @Test
    fun `a wrong pairing code is refused and every start makes a new code`() {
        controller.start()
        val first = (controller.state.value as StreamState.On)
        val wrong = if (first.code == "000000") "000001" else "000000"
        val client = StreamClient(URI("ws://127.0.0.1:${first.port}"), StreamMessage.Pair(wrong)) {}
        val e = runCatching { client.connect() }.exceptionOrNull()
        client.close()
        assertTrue(e?.message?.contains("pairing code wrong") == true, e?.message)
        val codes = HashSet<String>()
        repeat(5) {
            controller.stop()
            controller.start()
            codes += (controller.state.value as StreamState.On).code
        }
        assertTrue(codes.size >= 4, codes.toString())
    }

    @Test
    fun `start and stop leave the server's work to the control executor and say so, the capture held only while on`() {
        c.capture.release() // the test's own hold: the capture runs only while the controller holds it
        held.start()
        // The server is not started on the calling (main) thread: the screen shows that it starts.
        assertEquals(StreamState.Starting, held.state.value)
        assertEquals(1, queued.pending)
        assertFalse(c.capture.isRunning)
        assertTrue(held.isOn)
        held.start() // a second press meanwhile does nothing
        assertEquals(1, queued.pending)
        queued.runAll()
        val on = held.state.value as StreamState.On
        assertTrue(on.port > 0)
        assertTrue(c.capture.isRunning)

        held.stop()
        // The capture is let go at once; the connections close on the control executor.
        assertEquals(StreamState.Stopping, held.state.value)
        assertFalse(c.capture.isRunning)
        assertEquals(1, queued.pending)
        held.start() // refused until the server is closed
        assertEquals(1, queued.pending)
        queued.runAll()
        assertEquals(StreamState.Off, held.state.value)
        assertFalse(held.isOn)
        // Closed: the port is free again.
        ServerSocket().use { it.bind(InetSocketAddress("0.0.0.0", on.port)) }
    }

    @Test
    fun `stopped while starting, the server is closed after its start and the capture never held`() {
        c.capture.release() // the test's own hold: the capture runs only while the controller holds it
        held.start()
        held.stop()
        assertEquals(StreamState.Stopping, held.state.value)
        assertEquals(2, queued.pending)
        queued.runAll()
        assertEquals(StreamState.Off, held.state.value)
        assertFalse(c.capture.isRunning)
        assertFalse(held.isOn)
    }

    @Test
    fun `a taken port and a refused foreground service are failures shown as such`() {
        c.capture.release() // the test's own hold: the capture runs only while the controller holds it
        ServerSocket().use { taken ->
            taken.reuseAddress = false
            taken.bind(InetSocketAddress("0.0.0.0", 0))
            val onTaken = StreamController(c.capture, { metadata }, scope, port = taken.localPort, control = queued)
            onTaken.start()
            assertEquals(StreamState.Starting, onTaken.state.value)
            queued.runAll()
            // The user's words (what failed, what to do), not the system's.
            assertEquals(StreamState.Failed(R.string.stream_failure_port_in_use), onTaken.state.value)
            assertFalse(onTaken.isOn)
            assertFalse(c.capture.isRunning)
        }

        refusal = R.string.foreground_refused_background
        held.start()
        assertEquals(StreamState.Failed(R.string.foreground_refused_background), held.state.value)
        assertEquals(0, queued.pending)

        // The service refused later (as StreamService does): the stream stops and says why.
        refusal = null
        held.start()
        queued.runAll()
        assertTrue(held.state.value is StreamState.On)
        held.stop(failure = R.string.foreground_refused_permission)
        queued.runAll()
        assertEquals(StreamState.Failed(R.string.foreground_refused_permission), held.state.value)
        assertFalse(c.capture.isRunning)
    }

    @Test
    fun `while on, a UDP push to a host on the local network gets every message as JSON lines, and refuses others`() {
        DatagramSocket(InetSocketAddress(InetAddress.getLoopbackAddress(), 0)).use { receiver ->
            receiver.soTimeout = 10_000
            receiver.receiveBufferSize = 1 shl 20
            controller.pushUdp("127.0.0.1:9000") // not on: nothing
            assertEquals(StreamState.Off, controller.state.value)
            controller.start()
            controller.pushUdp(" 127.0.0.1:${receiver.localPort} ")
            val pushing = (controller.state.value as StreamState.On).udp as UdpView.Pushing
            assertEquals("127.0.0.1:${receiver.localPort}", pushing.target)
            for (i in 0 until 50) c.offer(SessionStream.GYROSCOPE, 1_000_000_000L + i * 5_000_000L, 0.01f * i, -0.02f, 0.003f)
            c.drain()
            c.nowNs += 1_000_000_000L
            c.drain()
            val got = ArrayList<StreamMessage>()
            val buf = ByteArray(65_536)
            while (got.count { it is StreamMessage.Sample } < 50) {
                val p = DatagramPacket(buf, buf.size)
                receiver.receive(p)
                val line = String(buf, 0, p.length, Charsets.UTF_8)
                assertTrue(line.endsWith("\n"), line)
                got += StreamCodec.decode(line.trimEnd(), "datagram")
            }
            assertEquals(metadata, (got.first() as StreamMessage.Hello).metadata)
            val samples = got.filterIsInstance<StreamMessage.Sample>()
            assertEquals(StreamMessage.Sample(SessionStream.GYROSCOPE, 1_000_000_000L + 7 * 5_000_000L, floatArrayOf(0.07f, -0.02f, 0.003f), 3), samples[7])

            controller.stopUdp()
            assertEquals(null, (controller.state.value as StreamState.On).udp)
            controller.pushUdp("laptop")
            assertEquals(UdpView.Failed("laptop", null), (controller.state.value as StreamState.On).udp)
            controller.pushUdp("8.8.8.8:9000")
            assertEquals(UdpView.Failed("8.8.8.8:9000", R.string.stream_failure_not_local), (controller.state.value as StreamState.On).udp)
        }
    }

    @Test
    fun `a UDP lookup that has not finished does not hold up a stop, and its push is closed when it finishes late`() {
        held.start()
        queued.runAll()
        assertTrue(held.state.value is StreamState.On)
        held.pushUdp("127.0.0.1:9000")
        assertEquals(UdpView.Starting("127.0.0.1:9000"), (held.state.value as StreamState.On).udp)
        assertEquals(1, lookups.pending)
        // The lookup still running (a slow name), the user stops: the server closes on the control thread at once.
        held.stop()
        assertEquals(StreamState.Stopping, held.state.value)
        queued.runAll()
        assertEquals(StreamState.Off, held.state.value)
        // The lookup finishes late: its push is given up (closed on the control thread), nothing is shown.
        lookups.runAll()
        assertEquals(1, queued.pending)
        queued.runAll()
        assertEquals(StreamState.Off, held.state.value)
    }

    @Test
    fun `host and port are read as the screen takes them`() {
        assertEquals("192.168.1.20" to 9000, StreamController.parseHostPort("192.168.1.20:9000"))
        assertEquals("laptop.local" to 1, StreamController.parseHostPort("laptop.local:1"))
        assertEquals("fd00::1" to 9000, StreamController.parseHostPort("[fd00::1]:9000"))
        for (bad in listOf("", "laptop", ":9000", "laptop:", "laptop:0", "laptop:65536", "lap top:9000", "laptop:90x")) {
            assertEquals(null, StreamController.parseHostPort(bad), bad)
        }
    }
}
