package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import java.net.DatagramPacket
import java.net.DatagramSocket
import java.net.InetAddress
import java.net.InetSocketAddress
import java.net.SocketTimeoutException
import org.junit.jupiter.api.AfterEach
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.assertThrows

/** The UDP push against a real DatagramSocket on loopback. */
class UdpPushTest {
    private val metadata = SessionMetadata(appVersion = "0.1.0", source = "Motion Fusion 0.1.0", startAnchor = ClockAnchor(1_764_000_000_000, 5_000_000_000))
    private val offer = StreamOffer("Motion Fusion 0.1.0", metadata, listOf(SessionStream.GYROSCOPE, SessionStream.ORIENTATION))
    private val receiver = DatagramSocket(InetSocketAddress(InetAddress.getLoopbackAddress(), 0)).apply {
        receiveBufferSize = 4 shl 20
        soTimeout = 10_000
    }
    private var push: UdpPush? = null

    @AfterEach
    fun end() {
        push?.stop()
        receiver.close()
    }

    private fun receive(): String {
        val buf = ByteArray(65_536)
        val p = DatagramPacket(buf, buf.size)
        receiver.receive(p)
        return String(buf, 0, p.length, Charsets.UTF_8)
    }

    @Test
    fun `each message is one JSON line in one datagram, the hello first and again, a status each second`() {
        val p = UdpPush(InetSocketAddress(InetAddress.getLoopbackAddress(), receiver.localPort), { offer }, helloIntervalNs = 2_000_000_000L).also { push = it }
        p.start()
        val published = ArrayList<StreamMessage>()
        // 3 s of sample time at 100 Hz, gyroscope and orientation, published in small steps so that the receiver keeps up.
        val got = ArrayList<StreamMessage>()
        for (k in 0 until 300) {
            val t = 1_000_000_000L + k * 10_000_000L
            val v = floatArrayOf(0.01f * k, -0.0123456f, 3.0e-5f)
            p.publishSample(SessionStream.GYROSCOPE, t, v, 3)
            p.publishOrientation(t + 1, 0.5, 0.5, 0.5, 0.5)
            published += StreamMessage.Sample(SessionStream.GYROSCOPE, t, v, 3)
            published += StreamMessage.Orientation(t + 1, 0.5, 0.5, 0.5, 0.5)
            // Read what this step sent: its two messages, and a hello or a status when one is due.
            while (got.count { it is StreamMessage.Sample || it is StreamMessage.Orientation } < published.size) {
                val line = receive()
                assertTrue(line.endsWith("\n") && line.indexOf('\n') == line.length - 1, line)
                got += StreamCodec.decode(line.trimEnd(), "datagram")
            }
        }
        assertEquals(published, got.filter { it is StreamMessage.Sample || it is StreamMessage.Orientation })
        val hellos = got.withIndex().filter { it.value is StreamMessage.Hello }
        assertEquals(0, hellos.first().index)
        assertEquals(metadata, (hellos.first().value as StreamMessage.Hello).metadata)
        // Every 2 s of sample time: at 0, 2 s.
        assertEquals(2, hellos.size)
        val statuses = got.filterIsInstance<StreamMessage.Status>()
        assertEquals(2, statuses.size, "$statuses") // 1 s and 2 s after the first sample
        assertEquals(0L, statuses.last().dropped)
        // The sender counts a datagram after sending it, so the receiver may hold the last one first: the
        // counts are read once the sender has ended (stop waits for it).
        p.stop()
        assertEquals(600L, p.sent)
        assertEquals(0L, p.droppedCount)
    }

    @Test
    fun `a full queue drops and counts, never blocks the caller`() {
        // A receiver that reads nothing; the sender thread not started: the queue fills at its bound.
        val p = UdpPush(InetSocketAddress(InetAddress.getLoopbackAddress(), receiver.localPort), { offer }, capacity = 64).also { push = it }
        for (k in 0 until 1000) p.publishOrientation(k * 1_000_000L, 1.0, 0.0, 0.0, 0.0)
        assertEquals(1000L - 64, p.droppedCount)
        p.start()
        // What was queued is sent once the sender runs.
        var data = 0
        while (data < 64) {
            val line = receive()
            if (StreamCodec.decode(line.trimEnd(), "datagram") is StreamMessage.Orientation) data++
        }
        assertThrows<SocketTimeoutException> {
            receiver.soTimeout = 300
            while (true) if (StreamCodec.decode(receive().trimEnd(), "datagram") is StreamMessage.Orientation) data++
        }
        assertEquals(64, data)
    }

    @Test
    fun `a hello too long for one datagram goes brief, then in parts that make the whole hello`() {
        val full = dev.motionfusion.core.session.SessionReader.open(java.nio.file.Paths.get("..", "samples", "sim-session.zip")).use { it.metadata }
        val big = StreamOffer("Motion Fusion 0.1.0", full, listOf(SessionStream.GYROSCOPE, SessionStream.ORIENTATION))
        assertTrue(StreamCodec.encode(StreamMessage.Hello(big.source, full, big.streams, null)).length > UdpPush.MAX_DATAGRAM_BYTES)
        val p = UdpPush(InetSocketAddress(InetAddress.getLoopbackAddress(), receiver.localPort), { big }).also { push = it }
        p.start()
        p.publishOrientation(1_000_000_000L, 1.0, 0.0, 0.0, 0.0)
        val lines = ArrayList<String>()
        while (lines.none { it.startsWith("{\"type\":\"orientation\"") }) {
            check(lines.size < 100) { "no orientation after ${lines.size} datagrams" }
            lines += receive()
        }
        assertTrue(lines.all { it.toByteArray().size <= UdpPush.MAX_DATAGRAM_BYTES }, lines.map { it.length }.toString())
        val brief = StreamCodec.decode(lines.first().trimEnd(), "datagram") as StreamMessage.Hello
        assertEquals(full.startAnchor, brief.metadata.startAnchor)
        val parts = lines.drop(1).filter { "\"hello_part\"" in it }
        val pieces = parts.map { Regex("\"base64\":\"([^\"]*)\"").find(it)!!.groupValues[1] }
        val whole = pieces.joinToString("") { String(java.util.Base64.getDecoder().decode(it), Charsets.ISO_8859_1) }.toByteArray(Charsets.ISO_8859_1)
        val hello = StreamCodec.decode(String(whole, Charsets.UTF_8).trimEnd(), "hello parts") as StreamMessage.Hello
        assertEquals(full, hello.metadata)
        assertTrue(parts.last().contains("\"part\":${parts.size},\"parts\":${parts.size}"), parts.last())
        assertEquals(0L, p.droppedCount)
    }

    @Test
    fun `a closed port is counted as dropped`() {
        val closed = DatagramSocket(InetSocketAddress(InetAddress.getLoopbackAddress(), 0)).let { val port = it.localPort; it.close(); port }
        val p = UdpPush(InetSocketAddress(InetAddress.getLoopbackAddress(), closed), { offer }).also { push = it }
        p.start()
        val n = 200
        // One at a time: each send meets the port-unreachable answer of the one before.
        for (k in 0 until n) {
            p.publishOrientation(k * 1_000_000L, 1.0, 0.0, 0.0, 0.0)
            val deadline = System.nanoTime() + 10_000_000_000L
            while (p.sent + p.droppedCount < k + 1) {
                check(System.nanoTime() < deadline) { "message $k neither sent nor dropped" }
                java.util.concurrent.locks.LockSupport.parkNanos(100_000)
            }
        }
        assertTrue(p.droppedCount >= n / 4, "sent ${p.sent}, dropped ${p.droppedCount}")
    }

    @Test
    fun `only a target on the local network`() {
        val e = assertThrows<IllegalArgumentException> { UdpPush(InetSocketAddress(InetAddress.getByName("8.8.8.8"), 9000), { offer }) }
        assertTrue(e.message!!.contains("not on the local network"), e.message)
        UdpPush(InetSocketAddress(InetAddress.getByName("192.168.1.20"), 9000), { offer }).stop()
        UdpPush(InetSocketAddress(InetAddress.getByName("10.0.0.2"), 9000), { offer }).stop()
    }
}
