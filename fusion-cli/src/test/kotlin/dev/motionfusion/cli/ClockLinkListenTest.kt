package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.stream.StreamOffer
import dev.motionfusion.stream.StreamServer
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.net.InetAddress
import java.net.InetSocketAddress
import java.nio.file.Files
import java.nio.file.Path
import java.util.concurrent.CountDownLatch
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/**
 * Two phones whose sensor clocks differ from the laptop's (and each other's) by seconds and tens of
 * ppm, each received by `fusion listen`: their sessions carry the clock exchanges, and `fusion align`
 * puts one on the other's clock through the laptop's (docs/SYNC.md).
 */
class ClockLinkListenTest {
    @TempDir lateinit var tmp: Path
    private val pool = Executors.newFixedThreadPool(2)
    private val servers = ArrayList<StreamServer>()

    @AfterEach
    fun tearDown() {
        servers.forEach { it.stop() }
        pool.shutdownNow()
    }

    private class Phone(val offsetNs: Long, val ppm: Double) {
        fun clock(laptopNs: Long) = laptopNs + offsetNs + Math.round(laptopNs * ppm * 1e-6)
    }

    private fun serve(phone: Phone, exchanges: CountDownLatch): StreamServer {
        val meta = SessionMetadata(source = "test phone", startAnchor = ClockAnchor(1_764_000_000_000, phone.clock(System.nanoTime())))
        return StreamServer(
            InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "271828", { StreamOffer("test phone", meta, listOf(SessionStream.GYROSCOPE)) },
            sensorClock = { phone.clock(System.nanoTime()) }, onClockExchange = { _, _ -> exchanges.countDown() },
        ).also { it.start(); servers += it }
    }

    @Test
    fun `sessions received by one laptop are put on one clock through their clock exchanges`() {
        val a = Phone(offsetNs = 5_000_000_000L, ppm = 0.0)
        val b = Phone(offsetNs = -3_000_000_000L, ppm = 50.0)
        val dirs = listOf(tmp.resolve("a"), tmp.resolve("b"))
        val latches = listOf(CountDownLatch(8), CountDownLatch(8))
        val s = listOf(serve(a, latches[0]), serve(b, latches[1]))
        val runs = s.indices.map { i -> pool.submit<CliResult> { fusion("listen", "ws://127.0.0.1:${s[i].port}", "--code", "271828", "-o", dirs[i].toString()) } }
        // Four exchanges a second: wait (bounded) for eight on each phone, while each streams a few gyroscope samples on its own clock.
        val phones = listOf(a, b)
        for (i in s.indices) {
            while (s[i].clients().none { it.paired }) {
                check(!runs[i].isDone) { runs[i].get().err }
                java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
            }
        }
        var k = 0
        while (latches.any { it.count > 0 }) {
            for (i in s.indices) s[i].publishSample(SessionStream.GYROSCOPE, phones[i].clock(System.nanoTime()), floatArrayOf(0.1f * (k % 7), 0f, 0f), 3)
            k++
            latches.forEach { it.await(20, TimeUnit.MILLISECONDS) }
            check(k < 3_000) { "fewer than 8 clock exchanges in a minute" }
        }
        s.forEach { it.stop() }
        for (r in runs) {
            val res = r.get(30, TimeUnit.SECONDS)
            assertEquals(ExitCode.OK, res.code, res.err)
            assertTrue(res.err.contains("clock: the phone's sensor clock is"), res.err)
        }
        for (d in dirs) SessionReader.open(d).use { assertTrue(it.metadata.clockLink != null && it.clockExchanges().size >= 7, "${it.clockExchanges().size} exchanges") }
        val r = fusion("align", dirs[0].toString(), dirs[1].toString(), "-o", tmp.resolve("offsets.csv").toString())
        assertEquals(ExitCode.OK, r.code, r.err)
        assertTrue(r.out.contains("| link |"), r.out)
        val row = Files.readAllLines(tmp.resolve("offsets.csv"))[2].split(',')
        val mid = SessionReader.open(dirs[1]).use { rd -> rd.events(setOf(SessionStream.GYROSCOPE)).use { e -> val t = ArrayList<Long>(); while (e.next()) t += e.timestampNs; t[t.size / 2] } }
        // The truth: b's time → the laptop's → a's.
        val laptop = Math.round((mid - b.offsetNs) / (1 + b.ppm * 1e-6))
        val expected = a.clock(laptop) - mid
        val offset = row[2].toLong()
        println("link: offset error ${(offset - expected) / 1e6} ms, stated ±${row[4].toLong() / 1e6} ms")
        assertTrue(Math.abs(offset - expected) < 2_000_000, "offset $offset, expected $expected (error ${(offset - expected) / 1e6} ms)")
        assertTrue(row[3].toDouble().isFinite(), "drift ${row[3]}")
        // A session of the same laptop and one without exchanges: link is refused when asked for.
        assertEquals(ExitCode.DATA_ERROR, fusion("align", dirs[0].toString(), "../samples/sim-session.zip", "--method", "link").code)
    }
}
