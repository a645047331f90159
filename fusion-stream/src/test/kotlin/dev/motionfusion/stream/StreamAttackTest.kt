package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamMessage
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows
import java.io.ByteArrayOutputStream
import java.io.EOFException
import java.io.IOException
import java.io.InputStream
import java.net.InetAddress
import java.net.InetSocketAddress
import java.net.Socket
import java.net.SocketException
import java.net.URI
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicLong

/**
 * The server against peers that do not play by the rules (docs/STREAMING.md, "Limits"): raw sockets on loopback,
 * from 127.0.0.1 and other addresses of 127/8. Every loop is bounded in count, every read in time (a socket timeout
 * that turns a hang into a failure); no assertion is about wall-clock time. Each test fails against a server without
 * the limit it is about.
 */
class StreamAttackTest {
    private val offer = StreamOffer(
        "Motion Fusion test",
        SessionMetadata(source = "test", startAnchor = ClockAnchor(1_764_000_000_000, 0)),
        listOf(SessionStream.GYROSCOPE, SessionStream.ORIENTATION),
    )
    private val servers = mutableListOf<StreamServer>()
    private val closeables = mutableListOf<AutoCloseable>()

    @AfterEach
    fun tearDown() {
        closeables.forEach { runCatching { it.close() } }
        servers.forEach { runCatching { it.stop() } }
    }

    private fun server(
        settings: StreamServerSettings = StreamServerSettings(),
        nanoTime: () -> Long = System::nanoTime,
        newCode: () -> String = StreamServer::randomPairingCode,
        onCode: (String) -> Unit = {},
        onFailure: (String) -> Unit = {},
        offer: () -> StreamOffer = { this.offer },
        onConfirmation: ((StreamClientInfo) -> Unit)? = null,
    ) = StreamServer(
        InetSocketAddress(InetAddress.getLoopbackAddress(), 0), CODE, offer, settings, nanoTime, newCode, onCode, onFailure, onConfirmation,
    ).also { it.start(); servers += it }

    /** A TCP connection to [s] from [local] (any address of 127/8), reads bounded by 10 s. */
    private fun raw(s: StreamServer, local: String = "127.0.0.1"): Socket = Socket().also { sock ->
        closeables += sock
        sock.bind(InetSocketAddress(local, 0))
        sock.connect(InetSocketAddress(InetAddress.getLoopbackAddress(), s.port), 10_000)
        sock.soTimeout = 10_000
    }

    private fun request(extra: String = "") =
        "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n" +
            "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n$extra\r\n"

    /** Sends the upgrade request; returns the status line of the answer. */
    private fun upgrade(sock: Socket, extra: String = ""): String {
        sock.getOutputStream().write(request(extra).toByteArray(Charsets.US_ASCII))
        val head = ByteArrayOutputStream()
        val input = sock.getInputStream()
        while (!head.toString(Charsets.US_ASCII).endsWith("\r\n\r\n")) {
            check(head.size() < 65_536) { "no end of the answer's header" }
            val b = input.read()
            if (b < 0) break
            head.write(b)
        }
        return head.toString(Charsets.US_ASCII).lineSequence().first()
    }

    /** A client's frame, masked with a zero key (valid, and the payload stays readable). */
    private fun frame(opcode: Int, payload: ByteArray): ByteArray = ByteArrayOutputStream().apply {
        write(0x80 or opcode)
        when {
            payload.size < 126 -> write(0x80 or payload.size)
            payload.size < 65_536 -> { write(0x80 or 126); write(payload.size shr 8); write(payload.size and 0xff) }
            else -> { write(0x80 or 127); for (k in 7 downTo 0) write(((payload.size.toLong() shr (8 * k)) and 0xff).toInt()) }
        }
        write(ByteArray(4))
        write(payload)
    }.toByteArray()

    private fun pairFrame(code: String) = frame(1, """{"type":"pair","schema":1,"code":"$code"}""".toByteArray())

    /** Reads the server's next text frame (bounded by the socket's timeout). */
    private fun textFrame(sock: Socket): String {
        val input = sock.getInputStream()
        input.byte()
        val len = input.byte() and 0x7f
        check(len < 126) { "a long frame" }
        return String(ByteArray(len) { input.byte().toByte() }, Charsets.UTF_8)
    }

    private fun InputStream.byte(): Int = read().also { if (it < 0) throw EOFException() }

    /**
     * Reads the server's frames until it closes: its close frame's code, or -1 when the connection just ended (reset, or
     * closed without a close frame). A connection still open after 10 s of silence fails the test.
     */
    private fun awaitEnd(sock: Socket): Int {
        val input = sock.getInputStream()
        try {
            repeat(10_000) {
                val opcode = input.byte() and 0x0f
                var len = (input.byte() and 0x7f).toLong()
                if (len == 126L) len = ((input.byte() shl 8) or input.byte()).toLong()
                else if (len == 127L) { len = 0; repeat(8) { len = (len shl 8) or input.byte().toLong() } }
                val payload = ByteArray(len.toInt()).also { p -> var off = 0; while (off < p.size) { val n = input.read(p, off, p.size - off); if (n < 0) throw EOFException(); off += n } }
                if (opcode == 8) return if (payload.size >= 2) ((payload[0].toInt() and 0xff) shl 8) or (payload[1].toInt() and 0xff) else 1005
            }
            error("more than 10,000 frames")
        } catch (_: EOFException) {
            return -1
        } catch (e: java.net.SocketTimeoutException) {
            throw AssertionError("the connection is still open after 10 s", e)
        } catch (_: SocketException) {
            return -1
        }
    }

    /** A laptop paired with the right code that counts the orientations it gets. */
    private inner class Laptop(s: StreamServer, code: String = CODE, name: String? = null) {
        val received = AtomicLong()
        val client = StreamClient(URI("ws://127.0.0.1:${s.port}"), StreamMessage.Pair(code, client = name)) { m ->
            if (m is StreamMessage.Orientation) received.incrementAndGet()
        }.also { closeables += it }

        /** Publishes [n] orientations and waits until they all arrived (bounded by 30 s). */
        fun getsAll(s: StreamServer, n: Int) {
            val before = received.get()
            val t0 = (before + 1) * 1_000_000_000L
            for (k in 0 until n) s.publishOrientation(t0 + k * 5_000_000L, 1.0, 0.0, 0.0, 0.0)
            val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
            while (received.get() < before + n) {
                check(System.nanoTime() < deadline) { "the paired client got ${received.get() - before} of $n" }
                java.util.concurrent.locks.LockSupport.parkNanos(200_000)
            }
        }
    }

    @Test
    fun `a frame header claiming 2 GiB is refused before anything is allocated, the paired client goes on`() {
        val failures = ConcurrentLinkedQueue<String>()
        val s = server(onFailure = { failures += it })
        val laptop = Laptop(s).apply { client.connect() }
        val sock = raw(s)
        assertTrue(upgrade(sock).startsWith("HTTP/1.1 101"))
        // 14 bytes: FIN and text, masked, a 64-bit length of 2^31 - 1, the mask.
        sock.getOutputStream().write(byteArrayOf(0x81.toByte(), 0xff.toByte(), 0, 0, 0, 0, 0x7f, 0xff.toByte(), 0xff.toByte(), 0xff.toByte(), 0, 0, 0, 0))
        assertEquals(1009, awaitEnd(sock), "closed as too big (1009)")
        // One byte over the limit before pairing is refused the same way.
        val over = raw(s)
        upgrade(over)
        over.getOutputStream().write(frame(1, ByteArray(StreamServerSettings().maxFrameBytes + 1) { 'x'.code.toByte() }))
        assertEquals(1009, awaitEnd(over))
        assertNull(s.failure)
        assertTrue(failures.isEmpty(), "$failures")
        laptop.getsAll(s, 200)
    }

    @Test
    fun `an upgrade request whose headers never end is cut off`() {
        val s = server()
        val laptop = Laptop(s).apply { client.connect() }
        val sock = raw(s)
        val out = sock.getOutputStream()
        out.write("GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n".toByteArray())
        val line = ("X-Filler: " + "a".repeat(90) + "\r\n").toByteArray()
        var written = 0
        var cut = false
        // At most 4 MiB: the server reads as closed past its limit, and writes after its close fail.
        while (written < 4 shl 20) {
            try {
                out.write(line)
                out.flush()
            } catch (_: IOException) {
                cut = true
                break
            }
            written += line.size
        }
        assertTrue(cut, "the server read $written bytes of headers and never closed the connection")
        laptop.getsAll(s, 200)
    }

    @Test
    fun `half-open upgrade requests are closed, the oldest first beyond the cap and the rest after the handshake timeout`() {
        var now = 0L
        val settings = StreamServerSettings(maxUnpaired = 16)
        val s = server(settings, nanoTime = { now })
        val socks = List(40) { raw(s).also { it.getOutputStream().write("GET / HTTP/1.1\r\n".toByteArray()) } }
        // Beyond 16 waiting connections each new one closes the oldest: the first 24 are gone.
        for (k in 0 until 24) assertEquals(-1, awaitEnd(socks[k]), "connection $k")
        now += settings.handshakeTimeoutNs - 1_000_000_000L
        s.closeUnpaired()
        // Within the timeout the last 16 are held; after it they are closed.
        socks[39].soTimeout = 300
        assertThrows<java.net.SocketTimeoutException> { socks[39].getInputStream().read() }
        socks[39].soTimeout = 10_000
        now += 2_000_000_000L
        s.closeUnpaired()
        for (k in 24 until 40) assertEquals(-1, awaitEnd(socks[k]), "connection $k")
        // A laptop then pairs.
        Laptop(s).client.connect(2_000)
    }

    @Test
    fun `connections that never send a code cannot hold the places, a laptop pairs within 2 s`() {
        val s = server()
        // Twice the paired clients' places and more than the unpaired cap, all upgraded and silent.
        val silent = List(24) { raw(s).also { sock -> assertTrue(upgrade(sock).startsWith("HTTP/1.1 101")) } }
        val laptop = Laptop(s)
        laptop.client.connect(2_000)
        laptop.getsAll(s, 100)
        // The oldest silent ones were closed to make room (4008).
        assertEquals(StreamServer.CLOSE_TOO_MANY, awaitEnd(silent[0]))
        // Paired clients still have their own limit.
        val paired = List(7) { Laptop(s).apply { client.connect(2_000) } }
        val ninth = Laptop(s)
        val e = assertThrows<IOException> { ninth.client.connect(5_000) }
        assertTrue("too many clients" in e.message!!, e.message)
        assertEquals(8, s.clients().count { it.paired })
        paired.forEach { it.getsAll(s, 10) }
    }

    @Test
    fun `wrong codes from many loopback addresses and pre-opened connections share one budget, then the code changes and pairing pauses`() {
        val codes = ArrayDeque(listOf("111111", "222222"))
        val shown = ConcurrentLinkedQueue<String>()
        var now = 0L
        val s = server(nanoTime = { now }, newCode = { codes.removeFirst() }, onCode = { shown += it })
        fun tryCode(local: String, code: String, sock: Socket = raw(s, local).also { upgrade(it) }): Int {
            sock.getOutputStream().write(pairFrame(code))
            return awaitEnd(sock)
        }
        // Eight connections opened before any try, each from an address of its own.
        val socks = List(8) { k -> raw(s, "127.0.0.${10 + k}").also { assertTrue(upgrade(it).startsWith("HTTP/1.1 101")) } }
        val ends = socks.mapIndexed { k, sock -> tryCode("", String.format("%06d", 100 + k), sock) }
        // Five wrong codes, from five addresses, made a new code and paused pairing: the other three were not looked at.
        assertEquals(List(5) { StreamServer.CLOSE_REFUSED } + List(3) { StreamServer.CLOSE_PAUSED }, ends)
        assertEquals(listOf("111111"), shown.toList())
        assertEquals("111111", s.pairingCode)
        // Rotating addresses during the pause: refused unread, even with the right code.
        for (k in 1..20) assertEquals(StreamServer.CLOSE_PAUSED, tryCode("127.0.1.$k", if (k == 20) "111111" else "999999"))
        // After the pause, five more wrong ones from new addresses: a second code, a second pause.
        now += StreamServerSettings().wrongCodePauseNs + 1
        for (k in 1..5) assertEquals(StreamServer.CLOSE_REFUSED, tryCode("127.0.2.$k", "999999"))
        assertEquals(listOf("111111", "222222"), shown.toList())
        // At most 5 codes tried per pause, whatever the addresses: 10 of 36 tries here were looked at.
        now += StreamServerSettings().wrongCodePauseNs + 1
        // The first code, the one an attacker might have been told, no longer pairs; the shown one does.
        assertEquals(StreamServer.CLOSE_REFUSED, tryCode("127.0.3.1", CODE))
        Laptop(s, "222222").client.connect()
    }

    @Test
    fun `a laptop that paired before pairs again during a pause, a new address does not`() {
        var now = 0L
        val s = server(nanoTime = { now }, newCode = { "111111" })
        Laptop(s).client.connect()
        for (k in 1..5) {
            val sock = raw(s, "127.0.4.$k")
            upgrade(sock)
            sock.getOutputStream().write(pairFrame("999999"))
            assertEquals(StreamServer.CLOSE_REFUSED, awaitEnd(sock))
        }
        // 127.0.0.1 paired before: it is let in with the new code; 127.0.5.1 is not looked at.
        Laptop(s, "111111").client.connect(2_000)
        val fresh = raw(s, "127.0.5.1")
        upgrade(fresh)
        fresh.getOutputStream().write(pairFrame("111111"))
        assertEquals(StreamServer.CLOSE_PAUSED, awaitEnd(fresh))
    }

    @Test
    fun `a browser page of a foreign origin is refused, an allowed origin and none are let in`() {
        val s = server(StreamServerSettings(allowedOrigins = setOf("http://localhost:8000")))
        val foreign = raw(s)
        val status = upgrade(foreign, "Origin: http://example.invalid\r\n")
        assertTrue(!status.startsWith("HTTP/1.1 101"), status)
        assertEquals(-1, awaitEnd(foreign))
        val allowed = raw(s)
        assertTrue(upgrade(allowed, "Origin: http://localhost:8000\r\n").startsWith("HTTP/1.1 101"))
        allowed.getOutputStream().write(pairFrame(CODE))
        val none = raw(s)
        assertTrue(upgrade(none).startsWith("HTTP/1.1 101"))
    }

    @Test
    fun `a binary first frame is refused`() {
        val s = server()
        val sock = raw(s)
        upgrade(sock)
        sock.getOutputStream().write(frame(2, """{"type":"pair","schema":1,"code":"$CODE"}""".toByteArray()))
        assertEquals(StreamServer.CLOSE_REFUSED, awaitEnd(sock))
        assertTrue(s.clients().none { it.paired })
    }

    @Test
    fun `a fatal error stops the server and is reported, never left looking on`() {
        val failures = ConcurrentLinkedQueue<String>()
        val reported = CountDownLatch(1)
        val s = server(
            onFailure = { failures += it; reported.countDown() },
            // What a server out of memory meets while it pairs a client.
            offer = { throw OutOfMemoryError("simulated") },
        )
        val sock = raw(s)
        upgrade(sock)
        sock.getOutputStream().write(pairFrame(CODE))
        assertTrue(reported.await(10, TimeUnit.SECONDS), "no failure reported")
        assertEquals(listOf("the stream server stopped: OutOfMemoryError: simulated"), failures.toList())
        assertEquals(failures.single(), s.failure)
    }

    @Test
    fun `with confirmation a right code waits for the phone's user, an allowed laptop pairs and later reconnects without asking`() {
        val asked = java.util.concurrent.LinkedBlockingQueue<StreamClientInfo>()
        val s = server(onConfirmation = { asked += it })
        val laptop = Laptop(s, name = "fusion listen on lab\u0007\n\u202e")
        val waitingFor = java.util.concurrent.LinkedBlockingQueue<String>()
        val pairing = java.util.concurrent.Executors.newSingleThreadExecutor()
        val hello = pairing.submit<StreamMessage.Hello> { laptop.client.connect(onWaiting = { waitingFor += it }) }
        pairing.shutdown()
        val request = asked.poll(10, TimeUnit.SECONDS) ?: throw AssertionError("nobody was asked")
        assertEquals("fusion listen on lab", request.name, "control and format characters removed")
        assertEquals("127.0.0.1", request.address)
        assertTrue(request.awaitingConfirmation && !request.paired)
        assertEquals(listOf(request.id), s.clients().filter { it.awaitingConfirmation }.map { it.id })
        assertEquals("the phone asks its user to allow this client", waitingFor.poll(10, TimeUnit.SECONDS))
        assertTrue(!hello.isDone, "no hello before the answer")
        assertTrue(s.allow(request.id))
        assertEquals(offer.streams, hello.get(10, TimeUnit.SECONDS).streams)
        assertTrue(!s.allow(request.id) && !s.deny(request.id), "an answer is given once")
        laptop.getsAll(s, 100)
        // The same address again (fusion listen restarted): paired at once, nobody asked.
        Laptop(s).client.connect(2_000)
        assertTrue(asked.isEmpty(), "$asked")
    }

    @Test
    fun `a denied client is closed (4010) and the code changes, an unanswered one is closed at the time limit (4011)`() {
        val asked = java.util.concurrent.LinkedBlockingQueue<StreamClientInfo>()
        val shown = ConcurrentLinkedQueue<String>()
        var now = 0L
        val s = server(nanoTime = { now }, newCode = { "111111" }, onCode = { shown += it }, onConfirmation = { asked += it })
        val sock = raw(s, "127.0.6.1")
        upgrade(sock)
        sock.getOutputStream().write(pairFrame(CODE))
        assertEquals("""{"type":"waiting","reason":"the phone asks its user to allow this client"}""", textFrame(sock))
        val first = asked.poll(10, TimeUnit.SECONDS)!!
        assertTrue(s.deny(first.id))
        assertEquals(StreamServer.CLOSE_DENIED, awaitEnd(sock))
        // Whoever asked knew the code: a new one is shown, the old one no longer pairs.
        assertEquals(listOf("111111"), shown.toList())
        assertEquals("111111", s.pairingCode)
        // No answer: held past the 10-s pairing limit, closed once the confirmation's limit has passed.
        val late = raw(s, "127.0.6.2")
        upgrade(late)
        late.getOutputStream().write(pairFrame("111111"))
        textFrame(late)
        asked.poll(10, TimeUnit.SECONDS)!!
        now += StreamServerSettings().confirmationTimeoutNs - 1_000_000_000L
        s.closeUnpaired()
        assertEquals(listOf(true), s.clients().filter { it.address == "127.0.6.2" }.map { it.awaitingConfirmation })
        now += 2_000_000_000L
        s.closeUnpaired()
        assertEquals(StreamServer.CLOSE_NOT_CONFIRMED, awaitEnd(late))
    }

    @Test
    fun `clients awaiting confirmation count among the unpaired, the oldest closed first`() {
        val asked = java.util.concurrent.LinkedBlockingQueue<StreamClientInfo>()
        val s = server(StreamServerSettings(maxUnpaired = 4), onConfirmation = { asked += it })
        val waiting = raw(s, "127.0.7.1")
        upgrade(waiting)
        waiting.getOutputStream().write(pairFrame(CODE))
        textFrame(waiting)
        val request = asked.poll(10, TimeUnit.SECONDS)!!
        List(4) { k -> raw(s, "127.0.7.${2 + k}").also { upgrade(it) } }
        assertEquals(StreamServer.CLOSE_TOO_MANY, awaitEnd(waiting))
        assertTrue(!s.allow(request.id), "no longer waiting")
    }

    private companion object {
        const val CODE = "482913"
    }
}
