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
    private fun serve(extra: List<SessionStream> = emptyList()): StreamServer {
        val reader = SessionReader.open(sample)
        val streams = reader.streams.filter { it in StreamCodec.STREAMABLE } + extra
        val s = StreamServer(
            InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "271828",
            { StreamOffer("test phone", reader.metadata, streams) },
            // Nothing may be dropped here: the whole session is handed over at once.
            StreamServerSettings(clientQueueFrames = 1_000_000, handOffCapacity = 1_000_000),
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
