package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.core.session.SessionMetadata
import java.io.IOException
import java.util.Base64
import java.net.DatagramPacket
import java.net.DatagramSocket
import java.net.InetSocketAddress
import java.util.concurrent.atomic.AtomicLong

/**
 * The live stream pushed over UDP (docs/STREAMING.md, "UDP push"): every message of schema 1 as one JSON line
 * (StreamCodec, then `\n`) in one datagram to [target], which must be on the local network
 * ([StreamServer.isLocalNetwork]). The hello goes first and again every [helloIntervalNs] of sample time (a
 * receiver started later learns the metadata), a status every [statusIntervalNs]. No datagram is longer than
 * [MAX_DATAGRAM_BYTES] (one Ethernet frame, never fragmented): a hello whose metadata does not fit goes with the
 * metadata's source and clock anchor only, followed by the whole hello line in `hello_part` datagrams (Base64 pieces).
 *
 * As the server, capture never waits for the network: the publish methods offer a message to a bounded queue of
 * [capacity] and return; a full queue drops it, and a datagram the system would not send counts as dropped too. The
 * socket is connected to [target], so a closed port (the ICMP answer) makes the next send fail and count as dropped;
 * hellos and statuses that fail count there too. One thread encodes and sends.
 */
public class UdpPush(
    public val target: InetSocketAddress,
    private val offer: () -> StreamOffer,
    private val capacity: Int = 4096,
    private val statusIntervalNs: Long = 1_000_000_000L,
    private val helloIntervalNs: Long = 10_000_000_000L,
) {
    init {
        require(!target.isUnresolved) { "cannot resolve ${target.hostString}" }
        require(StreamServer.isLocalNetwork(target.address)) { "${target.address.hostAddress} is not on the local network" }
        require(capacity in 16..1_000_000) { "capacity must be 16 to 1,000,000" }
    }

    private val handOff = HandOff(capacity, "stream-udp", ::sendOne)

    /** Messages the system would not send (hellos and statuses included). */
    private val unsent = AtomicLong()
    private val socket = DatagramSocket().apply {
        // Connected: the system then reports an unreachable port to the next send. A target the system has no route to
        // cannot be connected; each send to it then fails and is counted.
        try {
            connect(target)
        } catch (_: java.net.SocketException) {
        }
    }
    @Volatile private var running = false

    @Volatile public var sent: Long = 0L
        private set

    /** Messages not sent: the queue was full, or the system refused the datagram (hellos and statuses included). */
    public val droppedCount: Long get() = handOff.droppedCount + unsent.get()

    public fun start() {
        check(!running) { "already started" }
        running = true
        handOff.start()
    }

    /** Stops sending; what is queued is dropped. */
    public fun stop() {
        running = false
        handOff.stop()
        socket.close()
        handOff.awaitStopped(1000)
    }

    /** Hands a sensor sample to the sender; never blocks. [values] is copied. */
    public fun publishSample(stream: SessionStream, timestampNs: Long, values: FloatArray, accuracy: Int) {
        handOff.sample(stream, timestampNs, values, accuracy)
    }

    /** Hands the fused orientation (sensor → ENU, [w, x, y, z]) to the sender; never blocks. */
    public fun publishOrientation(timestampNs: Long, qw: Double, qx: Double, qy: Double, qz: Double) {
        handOff.orientation(timestampNs, qw, qx, qy, qz)
    }

    // The sender thread's ([handOff]): its encoding buffer, when the last hello and status went, what was sent then.
    private val sb = StringBuilder(256)
    private var helloT = Long.MIN_VALUE
    private var statusT = Long.MIN_VALUE
    private var sentAtStatus = 0L

    /** Sender thread: [m], sampled at [t], in its datagram; before it the hello when due, after it the status when due. */
    private fun sendOne(m: StreamMessage, t: Long) {
        if (helloT == Long.MIN_VALUE || t - helloT >= helloIntervalNs) {
            helloT = t
            val o = offer()
            if (!sendHello(sb, StreamMessage.Hello(o.source, o.metadata, o.streams, null))) unsent.incrementAndGet()
        }
        if (send(sb, m)) sent++ else unsent.incrementAndGet()
        if (statusT == Long.MIN_VALUE) statusT = t
        if (t - statusT >= statusIntervalNs) {
            val rate = (sent - sentAtStatus) * 1e9 / (t - statusT)
            sentAtStatus = sent
            statusT = t
            if (!send(sb, StreamMessage.Status(t, sent, droppedCount, rate))) unsent.incrementAndGet()
        }
    }

    /** One line in one datagram; false when the system would not send it (no route, the port unreachable, closed). */
    private fun send(sb: StringBuilder, m: StreamMessage): Boolean = sendBytes(line(sb, m))

    private fun line(sb: StringBuilder, m: StreamMessage): ByteArray {
        sb.setLength(0)
        StreamCodec.encodeTo(sb, m)
        sb.append('\n')
        return sb.toString().toByteArray(Charsets.UTF_8)
    }

    private fun sendBytes(bytes: ByteArray): Boolean = try {
        socket.send(if (socket.isConnected) DatagramPacket(bytes, bytes.size) else DatagramPacket(bytes, bytes.size, target))
        true
    } catch (_: IOException) {
        false
    }

    /**
     * The hello in one datagram when it fits; else a hello whose metadata is only its source and clock anchor, then the
     * whole hello line in `hello_part` datagrams. False when any of them was not sent.
     */
    private fun sendHello(sb: StringBuilder, hello: StreamMessage.Hello): Boolean {
        val whole = line(sb, hello)
        if (whole.size <= MAX_DATAGRAM_BYTES) return sendBytes(whole)
        val brief = hello.copy(metadata = SessionMetadata(source = hello.metadata.source, startAnchor = hello.metadata.startAnchor))
        var ok = sendBytes(line(sb, brief))
        val pieces = (whole.size + HELLO_PART_BYTES - 1) / HELLO_PART_BYTES
        val b64 = Base64.getEncoder()
        for (k in 0 until pieces) {
            val piece = whole.copyOfRange(k * HELLO_PART_BYTES, minOf(whole.size, (k + 1) * HELLO_PART_BYTES))
            val text = "{\"type\":\"hello_part\",\"part\":${k + 1},\"parts\":$pieces,\"base64\":\"${b64.encodeToString(piece)}\"}\n"
            ok = sendBytes(text.toByteArray(Charsets.US_ASCII)) && ok
        }
        return ok
    }

    public companion object {
        /** The longest datagram sent: fits one Ethernet frame (1,500 bytes) with the IP and UDP headers, over IPv6 too. */
        public const val MAX_DATAGRAM_BYTES: Int = 1400

        /** Bytes of the hello line in each `hello_part` (Base64: 4/3 as many characters, well within a datagram). */
        internal const val HELLO_PART_BYTES: Int = 960
    }
}
