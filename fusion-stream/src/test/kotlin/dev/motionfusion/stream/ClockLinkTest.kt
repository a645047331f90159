package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.core.sync.ClockExchange
import dev.motionfusion.core.sync.ClockTimeline
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertNull
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.net.InetAddress
import java.net.InetSocketAddress
import java.net.URI
import java.util.concurrent.ConcurrentLinkedQueue
import java.util.concurrent.LinkedBlockingQueue
import java.util.concurrent.TimeUnit

/**
 * Clock exchanges over the real link on loopback (docs/SYNC.md): the phone's sensor clock is the
 * laptop's shifted by 1,234.5 s and running 80 ppm fast; the exchanges put it back on the laptop's.
 */
class ClockLinkTest {
    private val offsetNs = 1_234_500_000_000L
    private val drift = 80e-6
    private fun phoneClock(laptopNs: Long) = laptopNs + offsetNs + Math.round(laptopNs * drift)

    private val offer = StreamOffer("test", SessionMetadata(source = "test", startAnchor = ClockAnchor(1_764_000_000_000, 0)), listOf(SessionStream.GYROSCOPE))
    private val closing = mutableListOf<AutoCloseable>()

    @AfterEach
    fun tearDown() = closing.reversed().forEach { runCatching { it.close() } }

    @Test
    fun `pings put the phone's sensor clock on the laptop's`() {
        val phoneSide = ConcurrentLinkedQueue<ClockExchange>()
        val names = ConcurrentLinkedQueue<String?>()
        // The server's own clock (of its limits) runs 20 ms ahead per ping, so its one-ping-per-10-ms limit never
        // depends on how fast this machine turns the pings round.
        val skip = java.util.concurrent.atomic.AtomicLong()
        val server = StreamServer(
            InetSocketAddress(InetAddress.getLoopbackAddress(), 0), "482913", { offer },
            nanoTime = { System.nanoTime() + skip.get() },
            sensorClock = { phoneClock(System.nanoTime()) }, onClockExchange = { c, e -> phoneSide += e; names += c.laptopClock },
        ).also { it.start(); closing += AutoCloseable { it.stop() } }
        val pongs = LinkedBlockingQueue<StreamMessage.Pong>()
        val client = StreamClient(URI("ws://127.0.0.1:${server.port}"), StreamMessage.Pair("482913")) { m -> if (m is StreamMessage.Pong) pongs += m }
            .also { closing += it }
        val hello = client.connect()
        assertTrue(hello.clock, "the hello says the phone answers pings")
        val laptopSide = ArrayList<ClockExchange>()
        val pinger = ClockPinger(System::nanoTime, { laptopSide += it }, "lab-laptop boot 1f2e")
        for (k in 0 until 150) {
            skip.addAndGet(2 * StreamServer.MIN_PING_INTERVAL_NS)
            val ping = pinger.ping()
            assertTrue(client.send(ping))
            val pong = pongs.poll(5, TimeUnit.SECONDS) ?: throw AssertionError("no answer to ping ${ping.id}")
            assertTrue(pinger.pong(pong) != null, "pong ${pong.id} completes its exchange")
        }
        assertEquals(150L, pinger.exchanges)
        assertEquals(0L, pinger.unanswered)
        val timeline = ClockTimeline(laptopSide)
        val mid = laptopSide[75].t1
        for (l in listOf(laptopSide.first().t1, mid, laptopSide.last().t4)) {
            val error = timeline.toLaptop(phoneClock(l)) - l
            assertTrue(Math.abs(error) < 500_000, "error ${error / 1e6} ms, stated ±${timeline.uncertaintyAt(phoneClock(l)) / 1e6} ms")
        }
        // The phone holds the same exchanges, each once its receipt came with the next ping.
        assertEquals(laptopSide.dropLast(1), phoneSide.toList())
        // Each with the laptop clock its pings name.
        assertEquals(setOf("lab-laptop boot 1f2e"), names.toSet())
        // The live estimate agrees.
        val live = pinger.mapping()!!
        assertTrue(Math.abs(live.toLaptop(phoneClock(mid)) - mid) < 1_000_000)
    }

    @Test
    fun `an answer to an older ping or a stranger is not used`() {
        var now = 1_000L
        val pinger = ClockPinger({ now })
        val first = pinger.ping()
        now += 100
        val second = pinger.ping()
        now += 100
        assertNull(pinger.pong(StreamMessage.Pong(first.id, first.t1Ns, 5_000, 5_010)))
        assertNull(pinger.pong(StreamMessage.Pong(second.id, second.t1Ns + 1, 5_000, 5_010)))
        assertTrue(pinger.pong(StreamMessage.Pong(second.id, second.t1Ns, 5_000, 5_010)) != null)
        assertNull(pinger.pong(StreamMessage.Pong(second.id, second.t1Ns, 5_000, 5_010)), "once only")
        assertEquals(1L, pinger.unanswered)
        // The next ping tells the phone when that answer arrived.
        val third = pinger.ping()
        assertEquals(second.id, third.previousId)
        assertEquals(now, third.previousT4Ns)
    }

    @Test
    fun `pings and pongs round-trip through the codec and a hello without clock stays without`() {
        for (m in listOf(StreamMessage.Ping(7, 123456789012345, 6, 123456789000000), StreamMessage.Ping(1, -5), StreamMessage.Ping(2, 3, 1, 2, "lab \"x\""), StreamMessage.Pong(7, 1, Long.MAX_VALUE, Long.MIN_VALUE))) {
            assertEquals(m, StreamCodec.decode(StreamCodec.encode(m), "test"))
        }
        val hello = StreamMessage.Hello("p", offer.metadata, listOf(SessionStream.GYROSCOPE), null)
        assertEquals(false, (StreamCodec.decode(StreamCodec.encode(hello), "test") as StreamMessage.Hello).clock)
        assertTrue((StreamCodec.decode(StreamCodec.encode(hello.copy(clock = true)), "test") as StreamMessage.Hello).clock)
    }
}
