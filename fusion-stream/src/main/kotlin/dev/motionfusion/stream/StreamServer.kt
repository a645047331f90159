package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import org.java_websocket.WebSocket
import org.java_websocket.WebSocketImpl
import org.java_websocket.framing.CloseFrame
import org.java_websocket.exceptions.WebsocketNotConnectedException
import org.java_websocket.handshake.ClientHandshake
import org.java_websocket.server.WebSocketServer
import java.io.IOException
import java.net.Inet6Address
import java.net.InetAddress
import java.net.InetSocketAddress
import java.security.MessageDigest
import java.util.concurrent.ArrayBlockingQueue
import java.util.concurrent.CopyOnWriteArrayList
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit
import java.util.concurrent.atomic.AtomicLong

/**
 * What a phone offers to the clients it streams to: the session [metadata] (device, sensors, the clock
 * anchor read when capture started, the live filter's settings), the [streams] it captures, and the
 * [source] name ("Motion Fusion 0.1.0").
 */
public data class StreamOffer(val source: String, val metadata: SessionMetadata, val streams: List<SessionStream>)

/**
 * Limits of a [StreamServer]: at most [maxClients] connections; each client's queue of frames not yet
 * written to its socket holds at most [clientQueueFrames] (beyond that its messages are dropped and
 * counted); the hand-off from the capture thread holds [handOffCapacity] messages; a status message
 * every [statusIntervalNs] of sample time. Pairing: a connection that has not sent a right code within
 * [pairingTimeoutNs] is closed (it would hold one of the [maxClients] places); an address that sent
 * [maxWrongCodes] wrong codes in a row is refused for [wrongCodeLockoutNs], so that the 6-digit code cannot be
 * found by trying (at 5 tries a minute, 10⁶ codes take about a year).
 */
public data class StreamServerSettings(
    val maxClients: Int = 8,
    val clientQueueFrames: Int = 2048,
    val handOffCapacity: Int = 16384,
    val statusIntervalNs: Long = 1_000_000_000L,
    val pairingTimeoutNs: Long = 10_000_000_000L,
    val maxWrongCodes: Int = 5,
    val wrongCodeLockoutNs: Long = 60_000_000_000L,
) {
    init {
        require(maxClients in 1..64) { "maxClients must be 1 to 64" }
        require(clientQueueFrames in 16..1_000_000) { "clientQueueFrames must be 16 to 1,000,000" }
        require(handOffCapacity in 16..1_000_000) { "handOffCapacity must be 16 to 1,000,000" }
        require(statusIntervalNs > 0) { "statusIntervalNs must be positive" }
        require(pairingTimeoutNs > 0) { "pairingTimeoutNs must be positive" }
        require(maxWrongCodes >= 1) { "maxWrongCodes must be at least 1" }
        require(wrongCodeLockoutNs >= 0) { "wrongCodeLockoutNs must not be negative" }
    }
}

/** One connected client as the phone's screen shows it. */
public data class StreamClientInfo(
    val address: String,
    val paired: Boolean,
    val streams: List<SessionStream>,
    val rateHz: Double?,
    val sent: Long,
    val dropped: Long,
    /** Messages per second this client got over the last status interval. */
    val achievedRateHz: Double,
    /**
     * The client does not keep up: its queue of unsent frames is full now, or messages were dropped for it
     * over the last status interval.
     */
    val stalled: Boolean = false,
)

/**
 * The phone side of the live stream (docs/STREAMING.md): a WebSocket server (Java-WebSocket) that sends
 * each paired client the samples and orientations handed to [publishSample] and [publishOrientation].
 *
 * Capture never waits for the network: the publish methods only offer a message to a bounded hand-off
 * queue and return (a full queue drops the message and counts it); one sender thread encodes each
 * message once and gives it to every client that asked for it, unless that client's unsent frames
 * already fill its queue (then it is dropped for that client alone, counted, and reported to it in the
 * next status message). A client must send the pairing code first; one from outside the local network
 * (not loopback, link-local, site-local or unique-local), a wrong code or a malformed first message is
 * refused and closed, as is one that sends no code in time or comes from an address locked out after wrong
 * codes ([StreamServerSettings]). [nanoTime] is the clock of those limits.
 */
public class StreamServer @JvmOverloads constructor(
    address: InetSocketAddress,
    pairingCode: String,
    private val offer: () -> StreamOffer,
    private val settings: StreamServerSettings = StreamServerSettings(),
    private val nanoTime: () -> Long = System::nanoTime,
) {
    private val code = pairingCode.toByteArray(Charsets.UTF_8)
    private val clients = CopyOnWriteArrayList<Client>()
    private val handOff = ArrayBlockingQueue<StreamMessage>(settings.handOffCapacity)
    private val handOffDropped = AtomicLong()
    private val started = CountDownLatch(1)

    @Volatile private var startError: Exception? = null

    @Volatile private var running = false
    private val sender = Thread(::sendLoop, "stream-sender").apply { isDaemon = true }

    private val server = object : WebSocketServer(address) {
        override fun onStart() = started.countDown()

        override fun onOpen(conn: WebSocket, handshake: ClientHandshake) {
            val remote = conn.remoteSocketAddress?.address
            when {
                remote == null || !isLocalNetwork(remote) -> conn.close(CLOSE_NOT_LOCAL, "only the local network and USB")
                lockedOut(remote.hostAddress) -> conn.close(CLOSE_LOCKED_OUT, "too many wrong pairing codes from this address: try again later")
                else -> synchronized(clients) {
                    // Checked and added together: connections open on several of the library's threads.
                    if (clients.size >= settings.maxClients) conn.close(CLOSE_TOO_MANY, "too many clients (${settings.maxClients})")
                    else Client(conn as WebSocketImpl, remote.hostAddress, nanoTime()).also { conn.setAttachment(it); clients.add(it) }
                }
            }
        }

        override fun onClose(conn: WebSocket, code: Int, reason: String?, remote: Boolean) {
            conn.getAttachment<Client>()?.let { clients.remove(it) }
        }

        override fun onMessage(conn: WebSocket, message: String) {
            val client = conn.getAttachment<Client>() ?: return
            if (client.paired) return // later requests are not part of schema 1
            pair(client, message)
        }

        override fun onError(conn: WebSocket?, ex: Exception) {
            if (conn == null) {
                startError = ex
                started.countDown()
            }
        }
    }.apply {
        isReuseAddr = true
        isTcpNoDelay = true
        connectionLostTimeout = 10
    }

    /** The port the server listens on (the one chosen by the system when it was given 0), once [start] returned. */
    public val port: Int get() = server.port

    /** Messages the capture thread handed over that the sender could not take in time (all clients missed them). */
    public val handOffDroppedCount: Long get() = handOffDropped.get()

    /** Starts listening; returns once the server accepts connections. @throws IOException when it cannot (port taken). */
    public fun start() {
        check(!running) { "already started" }
        running = true
        server.start()
        if (!started.await(10, TimeUnit.SECONDS)) throw IOException("the stream server did not start within 10 s")
        startError?.let { running = false; throw IOException("cannot listen on port ${server.address.port}: ${it.message}", it) }
        sender.start()
        pairingWatch.scheduleWithFixedDelay(::closeUnpaired, 1, 1, TimeUnit.SECONDS)
    }

    /**
     * Closes every connection and stops; waits at most [timeoutMs] for the connections to close. A connection
     * still open then (a stalled client: the library closes one only once its queue of frames has been sent)
     * is closed at once, its socket with it.
     */
    public fun stop(timeoutMs: Int = 1000) {
        running = false
        sender.interrupt()
        pairingWatch.shutdownNow()
        server.stop(timeoutMs, "the phone stopped streaming")
        sender.join(timeoutMs.toLong())
        for (conn in server.connections) (conn as? WebSocketImpl)?.closeConnection(CloseFrame.GOING_AWAY, "the phone stopped streaming")
        clients.clear()
    }

    /** Hands a sensor sample to the sender; never blocks. [values] is copied. */
    public fun publishSample(stream: SessionStream, timestampNs: Long, values: FloatArray, accuracy: Int) {
        if (clients.isEmpty()) return
        offer(StreamMessage.Sample(stream, timestampNs, values.copyOf(stream.valueCount.coerceAtMost(values.size)), accuracy))
    }

    /** Hands the fused orientation (sensor → ENU, [w, x, y, z]) to the sender; never blocks. */
    public fun publishOrientation(timestampNs: Long, qw: Double, qx: Double, qy: Double, qz: Double) {
        if (clients.isEmpty()) return
        offer(StreamMessage.Orientation(timestampNs, qw, qx, qy, qz))
    }

    /** The clients connected now. */
    public fun clients(): List<StreamClientInfo> = clients.map { it.info() }

    private fun offer(m: StreamMessage) {
        if (!handOff.offer(m)) handOffDropped.incrementAndGet()
    }

    private fun pair(client: Client, text: String) {
        val request = try {
            StreamCodec.decode(text, "client ${client.address}")
        } catch (e: DataFormatException) {
            return refuse(client, e.message ?: "malformed request")
        }
        if (request !is StreamMessage.Pair) return refuse(client, "the first message must be of type \"pair\"")
        if (!MessageDigest.isEqual(request.code.toByteArray(Charsets.UTF_8), code)) {
            wrongCode(client.address)
            return refuse(client, "pairing code wrong")
        }
        wrongCodes.remove(client.address)
        val offered = offer()
        val streams = request.streams?.filter { it in offered.streams } ?: offered.streams
        request.streams?.firstOrNull { it !in offered.streams }?.let { return refuse(client, "this phone does not capture ${it.key}") }
        client.subscribe(streams, request.rateHz)
        // The hello and the flag together: the sender waits for both, so every message published after the
        // client got its hello reaches it, and none goes before the hello.
        // [Client.accepted] is set before the hello goes out, so that whoever has received it finds the client
        // listed as paired.
        synchronized(client.pairing) {
            client.accepted = true
            client.conn.send(StreamCodec.encode(StreamMessage.Hello(offered.source, offered.metadata, streams, request.rateHz)))
            client.paired = true
        }
    }

    /** Wrong codes in a row per address, and until when (on [nanoTime]) the address is refused. */
    private class WrongCodes(var count: Int = 0, var lockedUntilNs: Long = 0L, var locked: Boolean = false)

    private val wrongCodes = java.util.concurrent.ConcurrentHashMap<String, WrongCodes>()

    private fun wrongCode(address: String) {
        val w = wrongCodes.computeIfAbsent(address) { WrongCodes() }
        synchronized(w) {
            if (++w.count >= settings.maxWrongCodes) {
                w.count = 0
                w.locked = true
                w.lockedUntilNs = nanoTime() + settings.wrongCodeLockoutNs
            }
        }
    }

    private fun lockedOut(address: String): Boolean {
        val w = wrongCodes[address] ?: return false
        return synchronized(w) { w.locked && nanoTime() - w.lockedUntilNs < 0 }
    }

    /**
     * Closes the connections that have not sent a right code within [StreamServerSettings.pairingTimeoutNs]; run
     * every second while the server runs (and by tests, with their clock).
     */
    internal fun closeUnpaired() {
        val now = nanoTime()
        for (c in clients) {
            if (!c.accepted && now - c.openedNs > settings.pairingTimeoutNs) {
                clients.remove(c)
                refuse(c, "no pairing code within ${settings.pairingTimeoutNs / 1_000_000_000} s")
            }
        }
    }

    private val pairingWatch = java.util.concurrent.Executors.newSingleThreadScheduledExecutor { r ->
        Thread(r, "stream-pairing").apply { isDaemon = true }
    }

    private fun refuse(client: Client, reason: String) {
        client.conn.send(StreamCodec.encode(StreamMessage.Error(reason)))
        client.conn.close(CLOSE_REFUSED, reason.take(100))
    }

    private fun sendLoop() {
        val sb = StringBuilder(256)
        while (running) {
            val m = try {
                handOff.take()
            } catch (_: InterruptedException) {
                return
            }
            val stream = when (m) {
                is StreamMessage.Sample -> m.stream
                is StreamMessage.Orientation -> SessionStream.ORIENTATION
                else -> continue
            }
            val t = when (m) {
                is StreamMessage.Sample -> m.timestampNs
                is StreamMessage.Orientation -> m.timestampNs
                else -> continue
            }
            var text: String? = null
            for (c in clients) {
                if (!c.paired && synchronized(c.pairing) { !c.paired }) continue
                if (!c.due(stream, t)) continue
                if (text == null) {
                    sb.setLength(0)
                    StreamCodec.encodeTo(sb, m)
                    text = sb.toString()
                }
                c.send(text, t)
            }
        }
    }

    private inner class Client(val conn: WebSocketImpl, val address: String, val openedNs: Long) {
        /** Held while the hello is queued and [paired] set. */
        val pairing = Any()

        /** The code was right: set just before the hello is queued (what [info] reports as paired). */
        @Volatile var accepted = false

        /** The hello is queued: the sender may send this client messages. */
        @Volatile var paired = false
        @Volatile private var streams: List<SessionStream> = emptyList()
        @Volatile private var rateHz: Double? = null
        private val wanted = BooleanArray(SessionStream.entries.size)
        private val nextDue = LongArray(SessionStream.entries.size) { Long.MIN_VALUE }
        private var periodNs = 0L

        @Volatile var sent = 0L
        @Volatile var dropped = 0L
        private var lastStatusT = Long.MIN_VALUE
        private var sentAtStatus = 0L
        private var droppedAtStatus = 0L

        /** Dropped over the last status interval. */
        @Volatile private var dropping = false
        private var droppedHandOffAtPairing = 0L

        @Volatile var achievedRateHz = 0.0

        fun subscribe(s: List<SessionStream>, rate: Double?) {
            streams = s
            rateHz = rate
            for (x in s) wanted[x.ordinal] = true
            periodNs = rate?.let { (1e9 / it).toLong() } ?: 0L
            droppedHandOffAtPairing = handOffDropped.get()
        }

        /** Whether this client asked for [stream] and, under its rate, the sample at [t] is due. */
        fun due(stream: SessionStream, t: Long): Boolean {
            val i = stream.ordinal
            if (!wanted[i]) return false
            if (periodNs == 0L) return true
            val next = nextDue[i]
            if (next != Long.MIN_VALUE && t < next) return false
            // Keep the average rate; after a gap, start again from this sample.
            nextDue[i] = if (next == Long.MIN_VALUE || t - next > periodNs) t + periodNs else next + periodNs
            return true
        }

        fun send(text: String, t: Long) {
            if (!conn.isOpen || conn.outQueue.size >= settings.clientQueueFrames || !offer(text)) {
                dropped++
            } else {
                sent++
            }
            if (lastStatusT == Long.MIN_VALUE) lastStatusT = t
            if (t - lastStatusT >= settings.statusIntervalNs) {
                achievedRateHz = (sent - sentAtStatus) * 1e9 / (t - lastStatusT)
                sentAtStatus = sent
                dropping = dropped > droppedAtStatus
                droppedAtStatus = dropped
                lastStatusT = t
                val lost = dropped + (handOffDropped.get() - droppedHandOffAtPairing)
                // A client that does not keep up gets its status once its queue has room again, with the drops so far.
                if (conn.outQueue.size < settings.clientQueueFrames) offer(StreamCodec.encode(StreamMessage.Status(t, sent, lost, achievedRateHz)))
            }
        }

        /**
         * Queues [text] on the connection; false when that failed (it closed meanwhile, or the library refused): one
         * client's end never stops the sender for the others.
         */
        private fun offer(text: String): Boolean = try {
            conn.send(text)
            true
        } catch (_: WebsocketNotConnectedException) {
            false
        } catch (_: RuntimeException) {
            false
        }

        fun info() = StreamClientInfo(
            address, accepted, streams, rateHz, sent, dropped, achievedRateHz,
            stalled = dropping || (paired && conn.outQueue.size >= settings.clientQueueFrames),
        )
    }

    public companion object {
        /** Close codes (4000–4999 are the application's): refused request, not from the local network, too many clients, an address locked out after wrong codes. */
        public const val CLOSE_REFUSED: Int = 4001
        public const val CLOSE_NOT_LOCAL: Int = 4003
        public const val CLOSE_TOO_MANY: Int = 4008
        public const val CLOSE_LOCKED_OUT: Int = 4029

        /** Loopback, link-local, site-local (10/8, 172.16/12, 192.168/16) or IPv6 unique-local (fc00::/7). */
        @JvmStatic
        public fun isLocalNetwork(a: InetAddress): Boolean =
            a.isLoopbackAddress || a.isLinkLocalAddress || a.isSiteLocalAddress ||
                (a is Inet6Address && (a.address[0].toInt() and 0xfe) == 0xfc)
    }
}
