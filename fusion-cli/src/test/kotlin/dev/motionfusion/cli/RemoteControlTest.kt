package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.ControlOutcome
import dev.motionfusion.stream.RemoteControl
import dev.motionfusion.stream.StreamClientInfo
import dev.motionfusion.stream.StreamOffer
import dev.motionfusion.stream.StreamServer
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.net.InetAddress
import java.net.InetSocketAddress
import java.util.Locale
import java.util.concurrent.ConcurrentLinkedQueue

/**
 * `fusion record start|stop|mark` against simulated phones on loopback whose sensor clocks are the laptop's shifted by
 * seconds and running up to ±100 ppm off (docs/SYNC.md, "Remote start").
 */
class RemoteControlTest {
    private val servers = ArrayList<StreamServer>()

    @AfterEach
    fun tearDown() = servers.forEach { it.stop() }

    /**
     * A simulated phone: sensor clock = laptop clock (System.nanoTime here) shifted by [offsetNs] and running [ppm] fast;
     * its sensor delivers a sample every [periodNs] of its own clock from [phaseNs]. A start keeps the first sample at or
     * after the command's `at` (as the app's recorder does), or the first after the command's arrival without one.
     */
    private class Phone(val offsetNs: Long, val ppm: Double, val phaseNs: Long, val periodNs: Long = 5_000_000) : RemoteControl {
        @Volatile override var allowed = true
        val commands = ConcurrentLinkedQueue<Pair<StreamClientInfo, StreamMessage.Control>>()

        /** Its first sample of the started recording, on its own clock. */
        @Volatile var firstSample: Long? = null

        fun clock(laptopNs: Long): Long = laptopNs + offsetNs + Math.round(laptopNs * ppm * 1e-6)

        /** The truth: phone time [p] on the laptop's clock. */
        fun toLaptop(p: Long): Double = (p - offsetNs) / (1 + ppm * 1e-6)

        override fun control(client: StreamClientInfo, command: StreamMessage.Control): ControlOutcome {
            commands += client to command
            if (command.command == StreamMessage.Control.Command.START) {
                val from = command.atNs ?: clock(System.nanoTime())
                firstSample = phaseNs + Math.floorDiv(from - phaseNs + periodNs - 1, periodNs) * periodNs
                return ControlOutcome(session = "session-${offsetNs / 1_000_000_000}")
            }
            return ControlOutcome()
        }
    }

    private fun serve(phone: Phone?, code: String): StreamServer {
        val meta = SessionMetadata(source = "test phone", startAnchor = ClockAnchor(1_764_000_000_000, 0))
        return StreamServer(
            InetSocketAddress(InetAddress.getLoopbackAddress(), 0), code, { StreamOffer("test phone", meta, listOf(SessionStream.GYROSCOPE)) },
            sensorClock = { phone?.clock(System.nanoTime()) ?: System.nanoTime() }, remoteControl = phone,
        ).also { it.start(); servers += it }
    }

    @Test
    fun `remote start on four phones, their first samples within 5 ms of each other on the laptop clock`() {
        val rounds = System.getProperty("remoteStart.rounds", "3").toInt()
        val random = java.util.Random(39)
        val spreads = ArrayList<Double>()
        val errors = ArrayList<Double>()
        val clockErrors = ArrayList<Double>()
        repeat(rounds) { round ->
            val phones = listOf(
                Phone(5_000_000_000L, 100.0, random.nextInt(5_000_000).toLong()),
                Phone(-3_000_000_000L, -100.0, random.nextInt(5_000_000).toLong()),
                Phone(12_345_678_901L, 37.0, random.nextInt(5_000_000).toLong()),
                Phone(-47_000_000_000L, -80.0, random.nextInt(5_000_000).toLong()),
            )
            val codes = listOf("100001", "200002", "300003", "400004")
            val s = phones.indices.map { serve(phones[it], codes[it]) }
            val r = fusion("record", "start", *s.map { "ws://127.0.0.1:${it.port}" }.toTypedArray(), "--code", codes.joinToString(","))
            assertEquals(ExitCode.OK, r.code, r.err + r.out)
            assertEquals(4, r.out.lines().count { "started (session-" in it && "clock ±" in it }, r.out)
            // The one instant the laptop chose, each phone's first sample on the laptop's clock (the truth).
            val commands = phones.map { it.commands.single().second }
            val instant = commands.map { it.laptopNs }.distinct().single()
            assertTrue(commands.all { it.laptopClock != null && it.atNs != null && it.command == StreamMessage.Control.Command.START })
            assertTrue(phones.flatMap { it.commands }.all { it.first.name!!.startsWith("fusion record on ") })
            clockErrors += phones.indices.map { Math.abs(phones[it].toLaptop(commands[it].atNs!!) - instant) / 1e6 }
            val firsts = phones.map { it.toLaptop(it.firstSample!!) }
            spreads += (firsts.max() - firsts.min()) / 1e6
            errors += firsts.map { (it - instant) / 1e6 }
            assertTrue(spreads.last() < 5.0, "round $round: first samples ${firsts.map { (it - instant) / 1e6 }} ms after the instant")
            s.forEach { it.stop() }
        }
        println(String.format(Locale.ROOT, "remote start, %d rounds of four phones: spread of the first samples median %.3f ms, max %.3f ms; first sample after the laptop's instant %.3f to %.3f ms; the instant on the phones' clocks off by median %.3f ms, max %.3f ms",
            rounds, spreads.sorted()[rounds / 2], spreads.max(), errors.min(), errors.max(), clockErrors.sorted()[clockErrors.size / 2], clockErrors.max()))
        // Never before the instant by more than the clock's error.
        assertTrue(errors.min() > -0.5, "a first sample ${errors.min()} ms before the instant")
    }

    @Test
    fun `stop and mark reach every phone, a mark with its label and the instant on each phone's clock`() {
        val phones = listOf(Phone(1_000_000_000L, 50.0, 0), Phone(-2_000_000_000L, -50.0, 0))
        val s = phones.map { serve(it, "424242") }
        val urls = s.map { "ws://127.0.0.1:${it.port}" }.toTypedArray()
        assertEquals(ExitCode.OK, fusion("record", "mark", *urls, "--code", "424242", "--label", "jump").code)
        assertEquals(ExitCode.OK, fusion("record", "stop", *urls, "--code", "424242").code)
        for (p in phones) {
            val (mark, stop) = p.commands.map { it.second }
            assertEquals(StreamMessage.Control.Command.MARK, mark.command)
            assertEquals("jump", mark.label)
            // The laptop's instant on this phone's clock, within a millisecond of the truth.
            assertTrue(Math.abs(p.toLaptop(mark.atNs!!) - mark.laptopNs) < 1e6, "${(p.toLaptop(mark.atNs!!) - mark.laptopNs) / 1e6} ms")
            assertEquals(StreamMessage.Control.Command.STOP, stop.command)
        }
    }

    @Test
    fun `a phone that does not allow remote control refuses and closes, the command says so with exit code 5`() {
        val off = Phone(0, 0.0, 0).also { it.allowed = false }
        val on = Phone(0, 0.0, 0)
        val s = listOf(serve(on, "111111"), serve(off, "222222"), serve(null, "333333"))
        val r = fusion("record", "start", *s.map { "ws://127.0.0.1:${it.port}" }.toTypedArray(), "--code", "111111,222222,333333")
        assertEquals(ExitCode.DENIED, r.code, r.out + r.err)
        val lines = r.out.trim().lines()
        assertTrue(lines[0].endsWith(")") && "started" in lines[0], r.out)
        assertTrue("refused: remote control is off on the phone" in lines[1] && "refused: remote control is off on the phone" in lines[2], r.out)
        assertTrue(off.commands.isEmpty(), "not carried out")
        // Closed by the phone: no paired client is left on the refusing phones.
        for (server in s.drop(1)) {
            val deadline = System.nanoTime() + 10_000_000_000L
            while (server.clients().isNotEmpty()) {
                check(System.nanoTime() < deadline) { "the refusing phone kept the connection" }
                java.util.concurrent.locks.LockSupport.parkNanos(1_000_000)
            }
        }
        assertEquals(ExitCode.USAGE, fusion("record", "reboot", "ws://127.0.0.1:1", "--code", "1").code)
        assertEquals(ExitCode.USAGE, fusion("record", "start", "ws://127.0.0.1:1", "--code", "1", "--label", "x").code)
    }
}
