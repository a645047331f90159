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
import java.util.concurrent.Executors
import java.util.concurrent.TimeUnit

/** `fusion listen URL URL URL -o DIR`: three simulated phones on loopback into one folder, one of them leaving and coming back. */
class ListenPhonesTest {
    @TempDir lateinit var tmp: Path
    private val pool = Executors.newSingleThreadExecutor()
    private val servers = ArrayList<StreamServer>()

    @AfterEach
    fun tearDown() {
        servers.forEach { it.stop() }
        pool.shutdownNow()
    }

    /** A simulated phone: its sensor clock [offsetNs] from the laptop's; on [port] (0: any). */
    private fun phone(offsetNs: Long, code: String, port: Int = 0): StreamServer {
        val meta = SessionMetadata(source = "test phone", startAnchor = ClockAnchor(1_764_000_000_000, offsetNs))
        return StreamServer(
            InetSocketAddress(InetAddress.getLoopbackAddress(), port), code, { StreamOffer("test phone", meta, listOf(SessionStream.GYROSCOPE)) },
            sensorClock = { System.nanoTime() + offsetNs },
        ).also { it.start(); servers += it }
    }

    private fun awaitPaired(s: StreamServer, run: java.util.concurrent.Future<CliResult>) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
        while (s.clients().none { it.paired }) {
            check(!run.isDone) { run.get().err }
            check(System.nanoTime() < deadline) { "fusion listen did not pair" }
            java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
        }
    }

    private fun awaitRows(csv: Path, rows: Int, run: java.util.concurrent.Future<CliResult>) {
        val deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(30)
        while (!Files.exists(csv) || Files.readAllLines(csv).count { it.isNotEmpty() } < rows + 1) {
            check(!run.isDone) { run.get().err }
            check(System.nanoTime() < deadline) { "$rows rows not written to $csv" }
            java.util.concurrent.locks.LockSupport.parkNanos(5_000_000)
        }
    }

    /** [n] gyroscope samples at 200 Hz of sample time from [t0Ns]. */
    private fun publish(s: StreamServer, t0Ns: Long, n: Int) {
        for (k in 0 until n) s.publishSample(SessionStream.GYROSCOPE, t0Ns + k * 5_000_000L, floatArrayOf(k.toFloat(), 0f, 0f), 3)
    }

    private fun count(dir: Path): Int = SessionReader.open(dir).use { r ->
        r.events(setOf(SessionStream.GYROSCOPE)).use { e -> var n = 0; while (e.next()) n++; n }
    }

    @Test
    fun `three phones into one folder, one leaving and coming back into a linked session`() {
        val offsets = listOf(5_000_000_000L, -3_000_000_000L, 12_000_000_000L)
        val codes = listOf("111111", "222222", "333333")
        val phones = offsets.indices.map { phone(offsets[it], codes[it]) }.toMutableList()
        val dir = tmp.resolve("live")
        val urls = phones.map { "ws://127.0.0.1:${it.port}" }
        val run = pool.submit<CliResult> { fusion("listen", *urls.toTypedArray(), "--code", codes.joinToString(","), "-o", dir.toString(), "--duration", "10") }
        phones.forEach { awaitPaired(it, run) }
        val names = urls.map { "127.0.0.1-" + it.substringAfterLast(':') }
        for (i in phones.indices) publish(phones[i], offsets[i], 100)
        // The second phone's 100 samples written (handed to the system within 0.5 s) before it goes.
        awaitRows(dir.resolve(names[1]).resolve("gyroscope.csv"), 100, run)
        // The second phone turns streaming off, and on again on the same port.
        val port = phones[1].port
        phones[1].stop()
        phones[1] = phone(offsets[1], codes[1], port)
        awaitPaired(phones[1], run)
        publish(phones[1], offsets[1] + 2_000_000_000L, 50)
        // One sample 20 s on ends each phone's --duration.
        for (i in phones.indices) publish(phones[i], offsets[i] + 20_000_000_000L, 1)
        val r = run.get(60, TimeUnit.SECONDS)
        assertEquals(ExitCode.OK, r.code, r.err)
        assertEquals((names + "${names[1]}.2").sorted(), Files.list(dir).use { s -> s.map { it.fileName.toString() }.sorted().toList() })
        assertEquals(listOf(100, 100, 100, 50), (names + "${names[1]}.2").map { count(dir.resolve(it)) })
        for (n in names + "${names[1]}.2") {
            SessionReader.open(dir.resolve(n)).use {
                assertTrue(it.metadata.complete, n)
                // One laptop clock links them all (fusion align --method link).
                assertTrue(it.metadata.clockLink != null, n)
            }
        }
        SessionReader.open(dir.resolve("${names[1]}.2")).use { assertTrue(it.metadata.source!!.endsWith("(connection 2)"), it.metadata.source) }
        assertTrue("the phone stopped streaming; trying to connect again every second" in r.err, r.err)
        // The table at the end: each phone, its state and clock.
        for (n in names) assertTrue(Regex("\\s+$n\\s+done\\s").containsMatchIn(r.err), r.err)
        assertTrue("3 phones, 4 sessions in" in r.err, r.err)
    }

    @Test
    fun `several addresses need -o, and one code or one per address`() {
        assertEquals(ExitCode.USAGE, fusion("listen", "ws://127.0.0.1:1", "ws://127.0.0.1:2", "--code", "1").code)
        val r = fusion("listen", "ws://127.0.0.1:1", "ws://127.0.0.1:2", "--code", "1,2,3", "-o", tmp.resolve("x").toString())
        assertEquals(ExitCode.USAGE, r.code)
        assertTrue("3 codes for 2 phones" in r.err, r.err)
        assertEquals(ExitCode.USAGE, fusion("listen", "ws://127.0.0.1:1", "ws://127.0.0.1:1", "--code", "1", "-o", tmp.resolve("y").toString()).code)
    }
}
