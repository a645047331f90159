package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.stream.StreamOffer
import dev.motionfusion.stream.StreamServer
import dev.motionfusion.stream.StreamServerSettings
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.net.InetAddress
import java.net.InetSocketAddress
import java.nio.file.Files
import java.nio.file.Path
import java.nio.file.Paths
import java.util.concurrent.Executors
import java.util.concurrent.Future
import java.util.concurrent.TimeUnit

/** `fusion listen` against the phone's server on loopback, fed the sample session's recorded streams. */
class ListenCommandTest {
    @TempDir lateinit var tmp: Path

    private val sample: Path = Paths.get("..", "samples", "sim-session.zip")
    private val pool = Executors.newSingleThreadExecutor()
    private var server: StreamServer? = null

    @AfterEach
    fun tearDown() {
        server?.stop()
        pool.shutdownNow()
    }

    /** Serves the sample session: every recorded stream, then one gyroscope sample 20 s later (the listeners stop at --duration). */
    private fun serve(extra: List<SessionStream> = emptyList(), onConfirmation: ((dev.motionfusion.stream.StreamClientInfo) -> Unit)? = null): StreamServer {
        val reader = SessionReader.open(sample)
        val streams = reader.streams.filter { it in StreamCodec.STREAMABLE } + extra
        val s = StreamServer(
            InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "271828",
            { StreamOffer("test phone", reader.metadata, streams) },
            // Nothing may be dropped here: the whole session is handed over at once.
            StreamServerSettings(clientQueueFrames = 1_000_000, handOffCapacity = 1_000_000),
            onConfirmationRequested = onConfirmation,
        )
        s.start()
        server = s
        return s
    }

    private fun publishAll(s: StreamServer) {
        var last = 0L
        SessionReader.open(sample).use { r ->
            r.events(r.streams.filterTo(java.util.EnumSet.noneOf(SessionStream::class.java)) { it in StreamCodec.STREAMABLE }).use { e ->
                while (e.next()) {
                    s.publishSample(e.stream, e.timestampNs, FloatArray(e.stream.valueCount) { e.values[it].toFloat() }, e.accuracy)
                    last = e.timestampNs
                }
            }
        }
        s.publishSample(SessionStream.GYROSCOPE, last + 20_000_000_000L, floatArrayOf(0f, 0f, 0f), 3)
    }

    private fun listen(vararg args: String): Future<CliResult> = pool.submit<CliResult> { fusion("listen", *args) }

    /** `fusion listen` from [s] into [dir] in a process of its own (to be killed or signalled), its standard error to [err]. */
    private fun forkListen(s: StreamServer, dir: java.nio.file.Path, err: java.io.File): Process {
        val javaBin = java.io.File(System.getProperty("java.home"), "bin/java").path
        return ProcessBuilder(
            listOf(javaBin, "-cp", System.getProperty("java.class.path"), "dev.motionfusion.cli.MainKt", "listen", "ws://127.0.0.1:${s.port}", "--code", "271828", "-o", dir.toString()),
        ).redirectError(err).redirectOutput(java.io.File(err.path + ".out")).start()
    }

    private fun awaitPaired(s: StreamServer) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
        while (s.clients().none { it.paired }) {
            check(System.nanoTime() < deadline) { "fusion listen did not pair" }
            java.util.concurrent.locks.LockSupport.parkNanos(100_000)
        }
    }

    @Test
    fun `a session written by listen replays exactly as the recording it was streamed from`() {
        val s = serve()
        val dir = tmp.resolve("live")
        val run = listen("ws://127.0.0.1:${s.port}", "--code", "271828", "-o", dir.toString(), "--duration", "30")
        awaitPaired(s)
        publishAll(s)
        val r = run.get(60, TimeUnit.SECONDS)
        assertEquals(0, r.code, r.err)
        assertTrue("dropped by the phone (this client did not keep up): 0" in r.err, r.err)
        val fromStream = fusion("replay", dir.toString())
        val fromFile = fusion("replay", sample.toString())
        assertEquals(0, fromStream.code, fromStream.err)
        assertEquals(fromFile.out, fromStream.out)
        assertTrue(fromFile.out.lines().size > 1000)
        SessionReader.open(dir).use { assertTrue(it.metadata.complete) }
    }

    @Test
    fun `CSV to standard output, the header first, one row per orientation`() {
        val s = serve(listOf(SessionStream.ORIENTATION))
        val run = listen("ws://127.0.0.1:${s.port}", "--code", "271828", "--csv", "--duration", "30")
        awaitPaired(s)
        // Orientations from the first instant on: none may come before the header.
        for (k in 0 until 500) s.publishOrientation(k * 5_000_000L, 1.0, 0.0, 0.0, 0.0)
        s.publishOrientation(40_000_000_000L, 1.0, 0.0, 0.0, 0.0)
        val r = run.get(60, TimeUnit.SECONDS)
        assertEquals(0, r.code, r.err)
        val lines = r.out.trim().lines()
        assertEquals("t_s,qw,qx,qy,qz,azimuth_deg,pitch_deg,roll_deg", lines.first())
        assertEquals(501, lines.size)
        assertEquals(listOf(0.0, 1.0, 0.0, 0.0, 0.0), lines[1].split(',').take(5).map { it.toDouble() })
    }

    @Test
    fun `a wrong code is refused with the phone's reason and exit code 3`() {
        val s = serve()
        val r = fusion("listen", "ws://127.0.0.1:${s.port}", "--code", "000000")
        assertEquals(ExitCode.IO_ERROR, r.code)
        assertTrue("pairing code wrong" in r.err, r.err)
    }

    @Test
    fun `nothing listening on the address is said in words, not as an exception's name`() {
        val port = java.net.ServerSocket(0).use { it.localPort }
        val r = fusion("listen", "ws://127.0.0.1:$port", "--code", "000000")
        assertEquals(ExitCode.IO_ERROR, r.code)
        assertTrue("nothing listening at that address and port" in r.err && "Exception" !in r.err, r.err)
    }

    @Test
    fun `a phone that asks its user, listen says it waits, exit code 5 when denied, the stream when allowed`() {
        val asked = java.util.concurrent.LinkedBlockingQueue<dev.motionfusion.stream.StreamClientInfo>()
        val s = serve(listOf(SessionStream.ORIENTATION), onConfirmation = { asked += it })
        val denied = listen("ws://127.0.0.1:${s.port}", "--code", "271828")
        val first = asked.poll(30, TimeUnit.SECONDS) ?: throw AssertionError("the phone was not asked")
        assertTrue(first.name!!.startsWith("fusion listen on "), first.name)
        s.deny(first.id)
        val r = denied.get(60, TimeUnit.SECONDS)
        assertEquals(ExitCode.DENIED, r.code, r.err)
        assertTrue("fusion: waiting for confirmation on the phone" in r.err, r.err)
        assertTrue("denied on the phone" in r.err && "Exception" !in r.err, r.err)
        // The deny made a new code; with it, and allowed this time, the stream comes.
        val run = listen("ws://127.0.0.1:${s.port}", "--code", s.pairingCode, "--csv", "--duration", "30")
        s.allow((asked.poll(30, TimeUnit.SECONDS) ?: throw AssertionError("the phone was not asked again")).id)
        awaitPaired(s)
        for (k in 0 until 10) s.publishOrientation(k * 5_000_000L, 1.0, 0.0, 0.0, 0.0)
        s.publishOrientation(40_000_000_000L, 1.0, 0.0, 0.0, 0.0)
        val allowed = run.get(60, TimeUnit.SECONDS)
        assertEquals(0, allowed.code, allowed.err)
        assertEquals(11, allowed.out.trim().lines().size, allowed.out)
    }

    /**
     * A phone that misbehaves, on a raw socket: answers the upgrade, sends the hello of the sample session, then what
     * [script] writes (frames from [textFrame], or raw bytes), then closes the socket without a close frame.
     */
    private fun fakePhone(script: (java.io.OutputStream) -> Unit): java.net.ServerSocket {
        val ss = java.net.ServerSocket(0, 1, InetAddress.getLoopbackAddress())
        val meta = SessionReader.open(sample).use { it.metadata }
        Thread {
            runCatching {
                ss.accept().use { sock ->
                    sock.soTimeout = 10_000
                    val input = sock.getInputStream()
                    val head = StringBuilder()
                    while (!head.endsWith("\r\n\r\n")) {
                        val b = input.read()
                        if (b < 0 || head.length > 65_536) return@use
                        head.append(b.toChar())
                    }
                    val key = head.lines().first { it.startsWith("Sec-WebSocket-Key:", ignoreCase = true) }.substringAfter(':').trim()
                    val accept = java.util.Base64.getEncoder().encodeToString(
                        java.security.MessageDigest.getInstance("SHA-1").digest((key + "258EAFA5-E914-47DA-95CA-C5AB0DC85B11").toByteArray()),
                    )
                    val out = sock.getOutputStream()
                    out.write("HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Accept: $accept\r\n\r\n".toByteArray())
                    // The client's pair message (masked, short): read, so that closing the socket later is a plain end.
                    input.read()
                    val len = input.read() and 0x7f
                    input.readNBytes(4 + len)
                    out.write(textFrame(StreamCodec.encode(dev.motionfusion.core.stream.StreamMessage.Hello("fake phone", meta, listOf(SessionStream.GYROSCOPE), null))))
                    script(out)
                    out.flush()
                }
            }
        }.apply { isDaemon = true }.start()
        return ss
    }

    /** One unmasked text frame (the server's side). */
    private fun textFrame(text: String): ByteArray {
        val p = text.toByteArray()
        val b = java.io.ByteArrayOutputStream()
        b.write(0x81)
        when {
            p.size < 126 -> b.write(p.size)
            p.size < 65_536 -> { b.write(126); b.write(p.size shr 8); b.write(p.size and 0xff) }
            else -> { b.write(127); for (k in 7 downTo 0) b.write(((p.size.toLong() shr (8 * k)) and 0xff).toInt()) }
        }
        b.write(p)
        return b.toByteArray()
    }

    private fun gyro(k: Int) = textFrame("""{"type":"sample","stream":"gyroscope","t":${k * 5_000_000L},"v":[0.1,0.2,0.3],"a":3}""")

    @Test
    fun `a connection lost is not a clean end, exit code 4 and the reason, the session closed`() {
        fakePhone { out -> for (k in 0 until 100) out.write(gyro(k)) }.use { ss ->
            val dir = tmp.resolve("lost")
            val r = fusion("listen", "ws://127.0.0.1:${ss.localPort}", "--code", "1", "-o", dir.toString())
            assertEquals(ExitCode.CONNECTION_LOST, r.code, r.err)
            assertTrue("ended: connection lost" in r.err, r.err)
            assertTrue("gyroscope" in r.err && "100 messages" in r.err, r.err)
            SessionReader.open(dir).use { assertEquals(100L, it.metadata.streams[SessionStream.GYROSCOPE]?.samples) }
        }
    }

    @Test
    fun `a malformed message mid-stream is skipped and counted, never a silent end`() {
        fakePhone { out ->
            for (k in 0 until 50) out.write(gyro(k))
            out.write(textFrame("""{"type":"sample","stream":"gyroscope","t":1,"v":[0.1,0.2],"a":3}"""))
            out.write(textFrame("""{"type":"sample","stream":"gyrosc"""))
            for (k in 50 until 100) out.write(gyro(k))
            out.write(byteArrayOf(0x88.toByte(), 2, 0x03, 0xe9.toByte())) // a close frame: going away (1001)
        }.use { ss ->
            val dir = tmp.resolve("malformed")
            val r = fusion("listen", "ws://127.0.0.1:${ss.localPort}", "--code", "1", "-o", dir.toString())
            assertEquals(ExitCode.OK, r.code, r.err)
            assertTrue("malformed messages skipped: 2" in r.err, r.err)
            assertTrue("skipped a malformed message" in r.err, r.err)
            assertTrue("ended: the phone stopped streaming" in r.err, r.err)
            SessionReader.open(dir).use { assertEquals(100L, it.metadata.streams[SessionStream.GYROSCOPE]?.samples) }
        }
    }

    @Test
    fun `a message over the limit ends with a clear error and exit code 1, the session closed, no stack trace`() {
        fakePhone { out ->
            for (k in 0 until 20) out.write(gyro(k))
            // A header claiming a 1 GiB text frame, then some of it.
            out.write(byteArrayOf(0x81.toByte(), 127, 0, 0, 0, 0, 0x40, 0, 0, 0))
            out.write(ByteArray(65_536) { 'x'.code.toByte() })
        }.use { ss ->
            val dir = tmp.resolve("big")
            val run = listen("ws://127.0.0.1:${ss.localPort}", "--code", "1", "-o", dir.toString())
            val r = run.get(30, TimeUnit.SECONDS)
            assertEquals(ExitCode.DATA_ERROR, r.code, r.err)
            assertTrue("over the limit of 1 MiB" in r.err, r.err)
            assertTrue("Exception" !in r.err && "\tat " !in r.err, r.err)
            // Closed, with the reason. Messages that came in the same read from the socket as the too-large header are
            // lost with it (the library drops that read whole): when that read held the hello, no session was begun.
            if (Files.exists(dir.resolve("meta.json"))) {
                SessionReader.open(dir).use {
                    assertTrue(it.metadata.complete)
                    assertTrue("over the limit" in it.metadata.endReason, it.metadata.endReason)
                }
            }
        }
    }

    @Test
    fun `the phone stopping is a clean end, exit code 0 with the reason`() {
        val s = serve()
        val run = listen("ws://127.0.0.1:${s.port}", "--code", "271828", "--csv")
        awaitPaired(s)
        // Counted once queued after the hello: the phone's close then comes after both.
        s.publishSample(SessionStream.GYROSCOPE, 0L, floatArrayOf(0f, 0f, 0f), 3)
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
        while (s.clients().singleOrNull()?.sent != 1L) {
            check(System.nanoTime() < deadline) { "nothing sent: ${s.clients()}" }
            java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
        }
        s.stop()
        val r = run.get(30, TimeUnit.SECONDS)
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue("ended: the phone stopped streaming; exit code 0" in r.err, r.err)
    }

    @Test
    fun `listen killed mid-stream leaves a session that recover repairs to every sample received`() {
        val s = serve()
        val dir = tmp.resolve("killed")
        val err = tmp.resolve("stderr").toFile()
        val p = forkListen(s, dir, err)
        try {
            awaitPaired(s)
            // 3 s of sample time, accelerometer and gyroscope at 200 Hz, then wait until the listener got them all.
            val n = 600
            for (k in 0 until n) {
                s.publishSample(SessionStream.ACCELEROMETER, k * 5_000_000L, floatArrayOf(0f, 0f, 9.81f), 3)
                s.publishSample(SessionStream.GYROSCOPE, k * 5_000_000L + 1, floatArrayOf(0.01f * k, 0f, 0f), 3)
            }
            val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
            while (s.clients().singleOrNull()?.sent != 2L * n) {
                check(System.nanoTime() < deadline) { "the listener did not get every message: ${s.clients()}" }
                java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
            }
            // Within a bound (the listener flushes at least once a second), every row is in its file; then a hard kill.
            val gyro = dir.resolve("gyroscope.csv")
            while (!Files.exists(gyro) || Files.readAllLines(gyro).size < n + 1) {
                check(System.nanoTime() < deadline) { "rows still unwritten: ${if (Files.exists(gyro)) Files.readAllLines(gyro).size - 1 else 0} of $n" }
                java.util.concurrent.locks.LockSupport.parkNanos(10_000_000)
            }
            p.destroyForcibly()
            assertTrue(p.waitFor(30, TimeUnit.SECONDS))
        } finally {
            p.destroyForcibly()
        }
        val rec = fusion("recover", dir.toString())
        assertEquals(ExitCode.OK, rec.code, rec.err)
        SessionReader.open(dir).use { r ->
            assertEquals(600L, r.metadata.streams[SessionStream.GYROSCOPE]?.samples)
            assertEquals(600L, r.metadata.streams[SessionStream.ACCELEROMETER]?.samples)
        }
    }

    @Test
    fun `listen stopped by a signal closes its session and prints the summary`() {
        val s = serve()
        val dir = tmp.resolve("term")
        val err = tmp.resolve("stderr-term").toFile()
        val p = forkListen(s, dir, err)
        try {
            awaitPaired(s)
            for (k in 0 until 100) s.publishSample(SessionStream.GYROSCOPE, k * 5_000_000L, floatArrayOf(0f, 0f, 0f), 3)
            // Until the rows are in the file (flushed at least once a second): the listener is past its start then.
            val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
            val gyro = dir.resolve("gyroscope.csv")
            while (!Files.exists(gyro) || Files.readAllLines(gyro).size < 101) {
                check(System.nanoTime() < deadline) { "rows still unwritten: ${s.clients()}" }
                java.util.concurrent.locks.LockSupport.parkNanos(10_000_000)
            }
            p.destroy() // SIGTERM: what Ctrl-C's SIGINT does too, shutdown hooks run
            assertTrue(p.waitFor(30, TimeUnit.SECONDS))
        } finally {
            p.destroyForcibly()
        }
        val text = err.readText()
        assertTrue("ended: interrupted" in text, text)
        assertTrue("100 messages" in text, text)
        SessionReader.open(dir).use { assertTrue(it.metadata.complete); assertEquals("interrupted", it.metadata.endReason) }
    }

    @Test
    fun `usage errors`() {
        for ((args, message) in listOf(
            listOf("http://x:1", "--code", "1") to "is not an address ws://HOST:PORT",
            listOf("ws://127.0.0.1:9") to "needs --code",
            listOf("ws://127.0.0.1:9", "--code", "1", "--streams", "barometer") to "unknown stream 'barometer'",
            listOf("ws://127.0.0.1:9", "--code", "1", "-o", tmp.toString(), "--csv") to "exclude each other",
        )) {
            val r = fusion("listen", *args.toTypedArray())
            assertEquals(ExitCode.USAGE, r.code, r.err)
            assertTrue(message in r.err, r.err)
        }
        Files.writeString(tmp.resolve("x"), "x")
        val r = fusion("listen", "ws://127.0.0.1:9", "--code", "1", "-o", tmp.toString())
        assertTrue("is not an empty folder" in r.err, r.err)
    }
}
