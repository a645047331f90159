package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamMessage
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.io.IOException
import java.net.InetAddress
import java.net.InetSocketAddress
import java.net.URI
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicLong

/**
 * The phone's server (Java-WebSocket) against the laptop's client on loopback. No assertion is about
 * wall-clock time: the capture side is paced by sample time, and waits are bounds that turn a hang
 * into a failure.
 */
class StreamServerTest {
    private val sevenStreams = listOf(
        SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER,
        SessionStream.GYROSCOPE_UNCALIBRATED, SessionStream.MAGNETOMETER_UNCALIBRATED,
        SessionStream.ROTATION_VECTOR, SessionStream.GAME_ROTATION_VECTOR,
    )
    private val offer = StreamOffer(
        "Motion Fusion test",
        SessionMetadata(source = "test", startAnchor = ClockAnchor(1_764_000_000_000, 0)),
        sevenStreams + SessionStream.ORIENTATION,
    )
    private val servers = mutableListOf<StreamServer>()
    private val clients = mutableListOf<AutoCloseable>()
    private val stallers = mutableListOf<CountDownLatch>()

    @AfterEach
    fun tearDown() {
        stallers.forEach { it.countDown() }
        clients.forEach { runCatching { it.close() } }
        servers.forEach { it.stop() }
    }

    private fun server(settings: StreamServerSettings = StreamServerSettings()) =
        StreamServer(InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "482913", { offer }, settings).also { it.start(); servers += it }

    private fun uri(s: StreamServer) = URI("ws://127.0.0.1:${s.port}")

    /** A client that counts what it gets, and can be stalled (its reading thread blocked). */
    private inner class Counting(s: StreamServer, pair: StreamMessage.Pair = StreamMessage.Pair("482913")) {
        val received = AtomicLong()
        val messages = ConcurrentLinkedQueue<StreamMessage>()
        val statuses = ConcurrentLinkedQueue<StreamMessage.Status>()
        val release = CountDownLatch(1).also { stallers += it }

        @Volatile var stalled = false
        private val lock = java.util.concurrent.locks.ReentrantLock()
        private val arrived = lock.newCondition()
        val client = StreamClient(uri(s), pair) { m ->
            if (stalled) release.await()
            if (m is StreamMessage.Status) statuses += m else {
                if (keep) messages += m
                received.incrementAndGet()
                lock.lock()
                try { arrived.signalAll() } finally { lock.unlock() }
            }
        }.also { clients += it }
        var keep = false

        fun awaitCount(n: Long) {
            val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(60)
            lock.lock()
            try {
                while (received.get() < n) {
                    val left = deadline - System.nanoTime()
                    check(left > 0) { "the client got ${received.get()} of $n messages" }
                    arrived.awaitNanos(left)
                }
            } finally {
                lock.unlock()
            }
        }
    }

    /** Waits for [done] to hold; a bound of 30 s turns a hang into a failure. */
    private fun awaitUntil(state: () -> Any = { "" }, done: () -> Boolean) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
        while (!done()) {
            check(System.nanoTime() < deadline) { "condition not reached within 30 s: ${state()}" }
            java.util.concurrent.locks.LockSupport.parkNanos(100_000)
        }
    }

    /** Publishes [ticks] sensor instants from instant [from] on: the seven streams at 200 Hz and the orientation. */
    private fun publish(s: StreamServer, from: Int, ticks: Int) {
        val step = 5_000_000L
        for (k in from until from + ticks) {
            val t = k * step
            for ((i, stream) in sevenStreams.withIndex()) {
                s.publishSample(stream, t + i, FloatArray(stream.valueCount) { (t % 1000).toFloat() + it * 0.25f + i }, 3)
            }
            s.publishOrientation(t + 7, 1.0, 0.0, 0.0, 0.0)
        }
    }

    @Test
    fun `seven streams at 200 Hz for 60 s, a fast client loses nothing while a stalled one is dropped to its bound`() {
        val settings = StreamServerSettings(clientQueueFrames = 512)
        val s = server(settings)
        val fast = Counting(s)
        fast.client.connect()
        val stalled = Counting(s)
        stalled.client.connect()
        stalled.stalled = true
        val perSecond = 200L * 8
        for (tenth in 0 until 600) {
            publish(s, tenth * 20, 20)
            // Capture goes on at the sensors' pace (160 messages every 0.1 s); a fast client keeps up with it.
            fast.awaitCount((tenth + 1) * perSecond / 10)
            if (tenth == 450) {
                // 45 s of sample time (72,000 messages, more than the sockets' buffers hold): the stalled client is being dropped.
                val mid = s.clients()
                assertEquals(2, mid.size, "$mid")
                assertTrue(mid.any { it.dropped > 0 && it.sent < 45 * perSecond }, "$mid")
                // Shown as stalled while its messages are being dropped; the fast client is not.
                assertTrue(mid.single { it.dropped > 0 }.stalled, "$mid")
                assertFalse(mid.single { it.dropped == 0L }.stalled, "$mid")
            }
        }
        assertEquals(60 * perSecond, fast.received.get())
        assertEquals(0L, s.handOffDroppedCount)
        // The stalled client never held the sender up: one more tenth of a second still reaches the fast one.
        publish(s, 600 * 20, 20)
        fast.awaitCount(60 * perSecond + perSecond / 10)
        val infos = s.clients()
        val quick = infos.single { it.sent >= 60 * perSecond }
        assertEquals(0L, quick.dropped)
        assertFalse(quick.stalled)
        // The stalled client was dropped to its bound; the library may also have closed it as unresponsive (it
        // answers no ping), which removes it from the list: both are what a stalled client should get.
        val slow = infos.singleOrNull { it !== quick }
        if (slow != null) assertTrue(slow.dropped > 0 && slow.sent < 60 * perSecond, "the stalled client was never dropped: $slow")
        assertTrue(fast.statuses.isNotEmpty() && fast.statuses.last().dropped == 0L, "${fast.statuses.lastOrNull()}")
        assertTrue(quick.achievedRateHz in 1500.0..1700.0, "rate ${quick.achievedRateHz}")
    }

    @Test
    fun `stopping closes a stalled client's connection too, whose queue never empties`() {
        val s = server(StreamServerSettings(clientQueueFrames = 512))
        val fast = Counting(s)
        fast.client.connect()
        val stalled = Counting(s)
        stalled.client.connect()
        stalled.stalled = true
        // At the sensors' pace (the fast client keeps up), until the stalled one's queue is full and it is dropped.
        val perSecond = 200L * 8
        var tenth = 0
        while (s.clients().none { it.dropped > 0 }) {
            check(tenth < 600) { "the stalled client was never dropped: ${s.clients()}" }
            publish(s, tenth * 20, 20)
            fast.awaitCount(++tenth * perSecond / 10)
        }
        s.stop()
        assertTrue(fast.client.awaitClose(10_000), "the fast client's connection is still open after stop")
        // The stalled client reads what had reached it, then finds the connection closed; before, the server closed
        // only connections whose queue had emptied, and this one stayed open with the server gone.
        stalled.release.countDown()
        assertTrue(stalled.client.awaitClose(10_000), "the stalled client's connection is still open after stop")
    }

    @Test
    fun `every message arrives exactly as published, subsets and rates as asked`() {
        val s = server()
        val all = Counting(s).apply { keep = true }
        all.client.connect()
        val subset = Counting(s, StreamMessage.Pair("482913", listOf(SessionStream.GYROSCOPE, SessionStream.ORIENTATION), 50.0)).apply { keep = true }
        val hello = subset.client.connect()
        assertEquals(listOf(SessionStream.GYROSCOPE, SessionStream.ORIENTATION), hello.streams)
        assertEquals(offer.metadata, hello.metadata)
        for (tenth in 0 until 20) {
            publish(s, tenth * 20, 20)
            all.awaitCount((tenth + 1) * 160L)
        }
        subset.awaitCount(2 * 2 * 50L)
        val samples = all.messages.filterIsInstance<StreamMessage.Sample>()
        assertEquals(2 * 200 * 7, samples.size)
        val first = samples.first { it.stream == SessionStream.MAGNETOMETER }
        assertEquals(StreamMessage.Sample(SessionStream.MAGNETOMETER, 2, floatArrayOf(2f, 2.25f, 2.5f), 3), first)
        val gyro = subset.messages.filterIsInstance<StreamMessage.Sample>()
        assertTrue(gyro.all { it.stream == SessionStream.GYROSCOPE })
        assertEquals(100, gyro.size)
        assertEquals(100, subset.messages.count { it is StreamMessage.Orientation })
        // 50 Hz out of 200 Hz: every fourth sample.
        assertEquals(List(99) { 20_000_000L }, gyro.zipWithNext { a, b -> b.timestampNs - a.timestampNs })
    }

    @Test
    fun `a wrong code, an unknown stream and a non-pair first message are refused`() {
        val s = server()
        for ((pair, reason) in listOf(
            StreamMessage.Pair("000000") to "pairing code wrong",
            StreamMessage.Pair("482913", listOf(SessionStream.ACCELEROMETER_UNCALIBRATED)) to "does not capture accelerometer_uncalibrated",
        )) {
            val c = StreamClient(uri(s), pair) {}.also { clients += it }
            val e = assertThrows<IOException> { c.connect() }
            assertTrue(reason in e.message!!, e.message)
        }
        assertTrue(s.clients().isEmpty() || s.clients().none { it.paired })
    }

    @Test
    fun `five wrong codes make a new code and pause pairing for a minute of the server's clock, and the old code is refused then`() {
        val shown = ConcurrentLinkedQueue<String>()
        var now = 0L
        val s = StreamServer(
            InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "482913", { offer }, StreamServerSettings(), nanoTime = { now },
            newPairingCode = { "123456" }, onPairingCodeChanged = { shown += it },
        ).also { it.start(); servers += it }
        fun attempt(code: String): String? = try {
            StreamClient(uri(s), StreamMessage.Pair(code)) {}.also { clients += it }.connect()
            null
        } catch (e: IOException) {
            e.message
        }
        for (k in 1..4) assertTrue(attempt("00000$k")!!.contains("pairing code wrong"))
        assertTrue(shown.isEmpty())
        assertEquals(null, attempt("482913"), "the right code after four wrong ones")
        assertTrue(attempt("000005")!!.contains("pairing code wrong"))
        assertEquals(listOf("123456"), shown.toList())
        assertEquals("123456", s.pairingCode)
        // Paused: not even the new code is looked at (this address sent a wrong code since it paired).
        assertTrue(attempt("123456")!!.contains("pairing paused"))
        now += 59_000_000_000L
        assertTrue(attempt("123456")!!.contains("pairing paused"))
        now += 2_000_000_000L
        assertTrue(attempt("482913")!!.contains("pairing code wrong"))
        assertEquals(null, attempt("123456"))
    }

    @Test
    fun `a connection that sends no code is closed after the pairing timeout of the server's clock`() {
        var now = 0L
        val s = StreamServer(InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "482913", { offer }, StreamServerSettings(), nanoTime = { now })
            .also { it.start(); servers += it }
        val closed = CountDownLatch(1)
        var closeCode = 0
        val silent = object : org.java_websocket.client.WebSocketClient(uri(s)) {
            override fun onOpen(handshake: org.java_websocket.handshake.ServerHandshake) {}
            override fun onMessage(message: String) {}
            override fun onClose(code: Int, reason: String?, remote: Boolean) {
                closeCode = code
                closed.countDown()
            }
            override fun onError(ex: Exception) {}
        }.also { clients += AutoCloseable { it.close() } }
        assertTrue(silent.connectBlocking(10, TimeUnit.SECONDS))
        awaitUntil({ s.clients() }) { s.clients().size == 1 }
        now += 9_000_000_000L
        s.closeUnpaired()
        assertEquals(1, s.clients().size, "open within the timeout")
        now += 2_000_000_000L
        s.closeUnpaired()
        assertTrue(closed.await(10, TimeUnit.SECONDS), "still open after the timeout")
        assertEquals(StreamServer.CLOSE_REFUSED, closeCode)
        assertTrue(s.clients().isEmpty())
    }

    @Test
    fun `clients that vanish are removed and the port is refused when taken`() {
        val s = server()
        val c = StreamClient(uri(s), StreamMessage.Pair("482913")) {}
        c.connect()
        assertEquals(1, s.clients().size)
        c.close()
        awaitUntil { s.clients().isEmpty() }
        val taken = StreamServer(InetSocketAddress(InetAddress.getLoopbackAddress(), s.port), "1", { offer })
        assertThrows<IOException> { taken.start() }
    }

    @Test
    fun `only the local network`() {
        for (a in listOf("127.0.0.1", "10.1.2.3", "172.16.0.9", "192.168.49.1", "169.254.1.1", "::1", "fe80::1", "fd12::1")) {
            assertTrue(StreamServer.isLocalNetwork(InetAddress.getByName(a)), a)
        }
        for (a in listOf("8.8.8.8", "172.32.0.1", "100.64.0.1", "2001:db8::1")) {
            assertTrue(!StreamServer.isLocalNetwork(InetAddress.getByName(a)), a)
        }
    }
}
