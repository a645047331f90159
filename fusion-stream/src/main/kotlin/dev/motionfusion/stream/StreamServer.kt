package dev.motionfusion.stream

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.core.sync.ClockExchange
import org.java_websocket.WebSocket
import org.java_websocket.WebSocketAdapter
import org.java_websocket.WebSocketImpl
import org.java_websocket.WebSocketServerFactory
import org.java_websocket.drafts.Draft
import org.java_websocket.drafts.Draft_6455
import org.java_websocket.enums.ReadyState
import org.java_websocket.exceptions.InvalidDataException
import org.java_websocket.exceptions.WebsocketNotConnectedException
import org.java_websocket.framing.CloseFrame
import org.java_websocket.handshake.ClientHandshake
import org.java_websocket.handshake.ServerHandshakeBuilder
import org.java_websocket.protocols.IProtocol
import org.java_websocket.protocols.Protocol
import org.java_websocket.server.WebSocketServer
import java.io.IOException
import java.nio.ByteBuffer
import java.nio.channels.ByteChannel
import java.nio.channels.SelectionKey
import java.nio.channels.SocketChannel
import java.security.SecureRandom
import java.util.Locale
import java.net.Inet6Address
import java.net.InetAddress
import java.net.InetSocketAddress
import java.security.MessageDigest
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
 * Limits of a [StreamServer] (docs/STREAMING.md, "Limits"). Paired clients: at most [maxClients]; each client's
 * queue of frames not yet written to its socket holds at most [clientQueueFrames] (beyond that its messages are
 * dropped and counted); the hand-off from the capture thread holds [handOffCapacity] messages; a status message
 * every [statusIntervalNs] of sample time.
 *
 * What a peer that has not paired can take, whoever it is: at most [maxUnpaired] such connections at once (from the
 * accepted socket on, the upgrade request still coming in included; a new one closes the oldest, so that a laptop
 * pairing now always gets in), [maxUnpairedBytes] bytes sent before pairing (the upgrade request and the pair
 * message), the upgrade request done within [handshakeTimeoutNs] and the pair message within [pairingTimeoutNs]
 * (both from the accepted socket). Every frame a client sends, before pairing and after, is at most [maxFrameBytes]
 * (a client sends only its pair message). After [maxWrongCodes] wrong pairing codes, from any address, the server
 * makes a new code (the phone shows it) and pauses pairing for [wrongCodePauseNs]: meanwhile only an address that
 * paired before (and sent no wrong code since) may pair, so that codes cannot be tried faster than [maxWrongCodes] per
 * pause, however many addresses the tries come from. A browser page is refused unless its Origin is one of [allowedOrigins]
 * (clients that are not browsers send none). A server that asks the phone's user to allow each new client
 * ([StreamServer]'s `onConfirmationRequested`) closes a request that was not answered within [confirmationTimeoutNs] of
 * its right code; until then it counts among the unpaired connections.
 */
public data class StreamServerSettings(
    val maxClients: Int = 8,
    val clientQueueFrames: Int = 2048,
    val handOffCapacity: Int = 16384,
    val statusIntervalNs: Long = 1_000_000_000L,
    val maxUnpaired: Int = 16,
    val maxUnpairedBytes: Int = 16_384,
    val maxFrameBytes: Int = 4096,
    val handshakeTimeoutNs: Long = 5_000_000_000L,
    val pairingTimeoutNs: Long = 10_000_000_000L,
    val maxWrongCodes: Int = 5,
    val wrongCodePauseNs: Long = 60_000_000_000L,
    val allowedOrigins: Set<String> = emptySet(),
    val confirmationTimeoutNs: Long = 60_000_000_000L,
) {
    init {
        require(maxClients in 1..64) { "maxClients must be 1 to 64" }
        require(clientQueueFrames in 16..1_000_000) { "clientQueueFrames must be 16 to 1,000,000" }
        require(handOffCapacity in 16..1_000_000) { "handOffCapacity must be 16 to 1,000,000" }
        require(statusIntervalNs > 0) { "statusIntervalNs must be positive" }
        require(maxUnpaired in 1..1024) { "maxUnpaired must be 1 to 1,024" }
        require(maxUnpairedBytes in 1024..1_048_576) { "maxUnpairedBytes must be 1,024 to 1,048,576" }
        require(maxFrameBytes in 256..1_048_576) { "maxFrameBytes must be 256 to 1,048,576" }
        require(handshakeTimeoutNs > 0) { "handshakeTimeoutNs must be positive" }
        require(pairingTimeoutNs > 0) { "pairingTimeoutNs must be positive" }
        require(maxWrongCodes >= 1) { "maxWrongCodes must be at least 1" }
        require(wrongCodePauseNs >= 0) { "wrongCodePauseNs must not be negative" }
        require(confirmationTimeoutNs > 0) { "confirmationTimeoutNs must be positive" }
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
    /** Identifies the connection for [StreamServer.allow] and [StreamServer.deny]. */
    val id: Long = 0,
    /** The name the client gave in its pair message (its own claim, cleaned of control characters, at most 40 characters). */
    val name: String? = null,
    /** Its code was right and the phone's user has not answered yet: [StreamServer.allow] or [StreamServer.deny]. */
    val awaitingConfirmation: Boolean = false,
    /** The clock its pings name (as meta.json's `clock_link`), once one did. */
    val laptopClock: String? = null,
)

/** What a [RemoteControl] made of a command: done ([reason] null), else why not; [session] names the recording concerned. */
public data class ControlOutcome @JvmOverloads constructor(val reason: String? = null, val session: String? = null) {
    /** Whether the command was carried out. */
    public val ok: Boolean get() = reason == null
}

/**
 * What a phone does with a paired client's remote-control commands (docs/STREAMING.md, "Remote control"): start or stop
 * a recording, or mark a moment. A [StreamServer] without one, or while [allowed] is false, refuses every command and
 * closes the connection ([StreamServer.CLOSE_NO_REMOTE_CONTROL]).
 */
public interface RemoteControl {
    /** Whether the phone's user allows remote control now (off unless the user turned it on). */
    public val allowed: Boolean

    /** Carries out [command] from [client] (on the connection's thread: quickly, or handed on); the outcome is the answer. */
    public fun control(client: StreamClientInfo, command: StreamMessage.Control): ControlOutcome
}

/**
 * The phone side of the live stream (docs/STREAMING.md): a WebSocket server (Java-WebSocket) that sends
 * each paired client the samples and orientations handed to [publishSample] and [publishOrientation].
 *
 * Capture never waits for the network: the publish methods only offer a message to a bounded hand-off
 * queue and return (a full queue drops the message and counts it); one sender thread encodes each
 * message once and gives it to every client that asked for it, unless that client's unsent frames
 * already fill its queue (then it is dropped for that client alone, counted, and reported to it in the
 * next status message). A client must send the pairing code first; one from outside the local network
 * (not loopback, link-local, site-local or unique-local), a browser page of a foreign origin, a wrong code or
 * a malformed or binary first message is refused and closed, as is one that does not pair in time or sends more
 * than an unpaired peer may ([StreamServerSettings]). [nanoTime] is the clock of those limits.
 *
 * After [StreamServerSettings.maxWrongCodes] wrong codes the server takes a new code from [newPairingCode] and
 * gives it to [onPairingCodeChanged] (on one of the server's threads), so that the phone shows it.
 *
 * With [onConfirmationRequested] given, a right code is not enough for a new client: it gets a `waiting` message, and the
 * callback (on one of the server's threads) the client as [StreamClientInfo.awaitingConfirmation], for the phone to ask
 * its user; [allow] then pairs it, [deny] closes it ([CLOSE_DENIED]) and makes a new code (whoever asked knew the code),
 * and no answer within [StreamServerSettings.confirmationTimeoutNs] closes it ([CLOSE_NOT_CONFIRMED]). An address
 * allowed once pairs again without asking for the rest of the server's life, unless it sends a wrong code. A failure that
 * stops the server while it runs (the library's fatal errors, such as running out of memory) goes to [onFailure]
 * once and is kept in [failure].
 */
public class StreamServer @JvmOverloads constructor(
    address: InetSocketAddress,
    pairingCode: String,
    private val offer: () -> StreamOffer,
    private val settings: StreamServerSettings = StreamServerSettings(),
    private val nanoTime: () -> Long = System::nanoTime,
    private val newPairingCode: () -> String = ::randomPairingCode,
    private val onPairingCodeChanged: (String) -> Unit = {},
    private val onFailure: (String) -> Unit = {},
    private val onConfirmationRequested: ((StreamClientInfo) -> Unit)? = null,
    /** The phone's sensor clock (elapsedRealtimeNanos on a phone), which [StreamMessage.Pong] reports (docs/SYNC.md). */
    private val sensorClock: () -> Long = System::nanoTime,
    /**
     * Each whole clock exchange with a paired client (the client's ping, this answer, the client's receipt), on the
     * connection's thread, with the client (its [StreamClientInfo.laptopClock] the clock its pings name).
     */
    private val onClockExchange: ((StreamClientInfo, ClockExchange) -> Unit)? = null,
    /** What the phone does with remote-control commands; null: refused, as while [RemoteControl.allowed] is false. */
    private val remoteControl: RemoteControl? = null,
) {
    @Volatile private var code = pairingCode.toByteArray(Charsets.UTF_8)
    private val codeLock = Any()
    private var wrongCodes = 0

    /** Pairing is paused until then (on [nanoTime]), after too many wrong codes; guarded by [codeLock]. */
    private var pausedUntilNs: Long? = null

    /**
     * Addresses that paired with a right code (and were allowed on the phone, when it asks) and sent no wrong code since:
     * they may pair during a pause, and without asking again. Guarded by [codeLock].
     */
    private val trusted = HashSet<String>()
    private val nextId = AtomicLong()
    private val clients = CopyOnWriteArrayList<Client>()

    /** Connections not paired yet, oldest first, from their accepted socket on (guarded by itself). */
    private val unpaired = ArrayDeque<Client>()
    private val handOff = HandOff(settings.handOffCapacity, "stream-sender", ::sendToClients)
    private val started = CountDownLatch(1)

    @Volatile private var startError: Exception? = null

    @Volatile private var listening = false

    @Volatile private var running = false

    @Volatile private var failed: String? = null

    private val server = object : WebSocketServer(
        address,
        listOf<Draft>(Draft_6455(emptyList(), listOf<IProtocol>(Protocol("")), settings.maxFrameBytes)),
    ) {
        override fun onStart() {
            listening = true
            started.countDown()
        }

        override fun onWebsocketHandshakeReceivedAsServer(conn: WebSocket, draft: Draft, request: ClientHandshake): ServerHandshakeBuilder {
            // Browsers send the page's origin; other clients (fusion listen, Python's websockets) none.
            val origin = request.getFieldValue("Origin")
            if (origin.isNotEmpty() && origin !in settings.allowedOrigins) {
                throw InvalidDataException(CloseFrame.POLICY_VALIDATION, "origin not allowed")
            }
            return super.onWebsocketHandshakeReceivedAsServer(conn, draft, request)
        }

        override fun onOpen(conn: WebSocket, handshake: ClientHandshake) {
            val client = conn.getAttachment<Client>() ?: return conn.close(CLOSE_REFUSED, "unknown connection")
            val remote = conn.remoteSocketAddress?.address
            if (remote == null || !isLocalNetwork(remote)) {
                forget(client)
                return conn.close(CLOSE_NOT_LOCAL, "only the local network and USB")
            }
            client.address = remote.hostAddress
            clients.add(client)
        }

        override fun onClose(conn: WebSocket, code: Int, reason: String?, remote: Boolean) {
            conn.getAttachment<Client>()?.let { clients.remove(it); forget(it) }
        }

        override fun onMessage(conn: WebSocket, message: String) {
            val received = sensorClock()
            val client = conn.getAttachment<Client>() ?: return
            // After the hello only pings are answered (docs/SYNC.md); one waiting for the phone's answer has made its request.
            if (client.paired) {
                return if (message.startsWith(CONTROL_PREFIX)) control(client, message) else ping(client, message, received)
            }
            if (client.accepted || client.awaiting != null) return
            pair(client, message)
        }

        override fun onMessage(conn: WebSocket, message: ByteBuffer) {
            val client = conn.getAttachment<Client>() ?: return
            if (!client.accepted && client.awaiting == null) refuse(client, "the first message must be a text frame of type \"pair\"")
        }

        override fun onError(conn: WebSocket?, ex: Exception) {
            if (!listening) {
                startError = ex
                started.countDown()
                return
            }
            // The library stops the whole server after these (its worker and selector threads end).
            val cause = ex.cause ?: ex
            if (conn == null || cause is VirtualMachineError || cause is LinkageError) fail(cause)
        }
    }.apply {
        isReuseAddr = true
        isTcpNoDelay = true
        connectionLostTimeout = CONNECTION_LOST_TIMEOUT_S
        setWebSocketFactory(object : WebSocketServerFactory {
            override fun createWebSocket(a: WebSocketAdapter, d: Draft): WebSocketImpl = createWebSocket(a, listOf(d))

            override fun createWebSocket(a: WebSocketAdapter, d: List<Draft>): WebSocketImpl =
                WebSocketImpl(a, d).also { admit(it) }

            override fun wrapChannel(channel: SocketChannel, key: SelectionKey): ByteChannel = Limited(channel, key)

            override fun close() = Unit
        })
    }

    /** The port the server listens on (the one chosen by the system when it was given 0), once [start] returned. */
    public val port: Int get() = server.port

    /** The pairing code in force: the one given, or the last one made after too many wrong codes. */
    public val pairingCode: String get() = String(code, Charsets.UTF_8)

    /** Why the server stopped by itself while running, or null. */
    public val failure: String? get() = failed

    /** Messages the capture thread handed over that the sender could not take in time (all clients missed them). */
    public val handOffDroppedCount: Long get() = handOff.droppedCount

    /** Starts listening; returns once the server accepts connections. @throws IOException when it cannot (port taken). */
    public fun start() {
        check(!running) { "already started" }
        running = true
        server.start()
        if (!started.await(10, TimeUnit.SECONDS)) throw IOException("the stream server did not start within 10 s")
        startError?.let { running = false; throw IOException("cannot listen on port ${server.address.port}: ${it.message}", it) }
        handOff.start()
        pairingWatch.scheduleWithFixedDelay(::closeUnpaired, 1, 1, TimeUnit.SECONDS)
        pairingWatch.scheduleWithFixedDelay({ for (c in clients) demandWrite(c) }, 1, 1, TimeUnit.SECONDS)
    }

    /**
     * Closes every connection and stops; waits at most [timeoutMs] for the connections to close. A connection
     * still open then (a stalled client: the library closes one only once its queue of frames has been sent)
     * is closed at once, its socket with it.
     */
    public fun stop(timeoutMs: Int = 1000) {
        running = false
        handOff.stop()
        pairingWatch.shutdownNow()
        server.stop(timeoutMs, "the phone stopped streaming")
        handOff.awaitStopped(timeoutMs.toLong())
        for (conn in server.connections) (conn as? WebSocketImpl)?.closeConnection(CloseFrame.GOING_AWAY, "the phone stopped streaming")
        val half = synchronized(unpaired) { unpaired.toList().also { unpaired.clear() } }
        for (c in half) c.conn.closeConnection(CloseFrame.GOING_AWAY, "the phone stopped streaming")
        clients.clear()
    }

    /** Hands a sensor sample to the sender; never blocks. [values] is copied. */
    public fun publishSample(stream: SessionStream, timestampNs: Long, values: FloatArray, accuracy: Int) {
        if (clients.isEmpty()) return
        handOff.sample(stream, timestampNs, values, accuracy)
    }

    /** Hands the fused orientation (sensor → ENU, [w, x, y, z]) to the sender; never blocks. */
    public fun publishOrientation(timestampNs: Long, qw: Double, qx: Double, qy: Double, qz: Double) {
        if (clients.isEmpty()) return
        handOff.orientation(timestampNs, qw, qx, qy, qz)
    }

    /** The clients connected now (the upgrade request done). */
    public fun clients(): List<StreamClientInfo> = clients.map { it.info() }

    private fun fail(cause: Throwable) {
        val reason = "the stream server stopped: ${cause.javaClass.simpleName}${cause.message?.let { ": $it" } ?: ""}"
        synchronized(this) {
            if (failed != null) return
            failed = reason
        }
        running = false
        handOff.stop()
        onFailure(reason)
    }

    /** A socket was accepted: it is unpaired until its code is right; over [StreamServerSettings.maxUnpaired] the oldest goes. */
    private fun admit(conn: WebSocketImpl) {
        val client = Client(conn, nanoTime())
        conn.setAttachment(client)
        val evicted = ArrayList<Client>()
        synchronized(unpaired) {
            unpaired.removeAll { it.conn.readyState == ReadyState.CLOSED }
            unpaired.addLast(client)
            while (unpaired.size > settings.maxUnpaired) evicted += unpaired.removeFirst()
        }
        for (c in evicted) drop(c, CLOSE_TOO_MANY, "too many connections waiting to pair (${settings.maxUnpaired})")
    }

    private fun forget(client: Client) {
        synchronized(unpaired) { unpaired.remove(client) }
    }

    /** Closes an unpaired connection: one whose upgrade is done gets the reason, one still in its upgrade request only the closed socket. */
    private fun drop(client: Client, closeCode: Int, reason: String) {
        clients.remove(client)
        if (client.conn.readyState == ReadyState.OPEN) refuse(client, reason, closeCode)
        else client.conn.closeConnection(CloseFrame.NEVER_CONNECTED, reason)
    }

    private fun pair(client: Client, text: String) {
        val request = try {
            StreamCodec.decode(text, "client ${client.address}")
        } catch (e: DataFormatException) {
            return refuse(client, e.message ?: "malformed request")
        }
        if (request !is StreamMessage.Pair) return refuse(client, "the first message must be of type \"pair\"")
        client.name = request.client?.let(::cleanName)
        var newCode: String? = null
        val verdict = synchronized(codeLock) {
            val now = nanoTime()
            val until = pausedUntilNs
            when {
                // Not even looked at: a pause lets no new address try.
                until != null && now - until < 0 && client.address !in trusted -> PAUSED
                MessageDigest.isEqual(request.code.toByteArray(Charsets.UTF_8), code) -> when {
                    client.address in trusted -> RIGHT
                    onConfirmationRequested != null -> {
                        // Awaiting the phone's user, under the same lock as a deny's new code.
                        client.awaiting = request
                        client.awaitingSinceNs = now
                        CONFIRM
                    }
                    else -> {
                        trusted += client.address
                        RIGHT
                    }
                }
                else -> {
                    trusted -= client.address
                    // One budget for the whole server, whichever address the tries come from.
                    if (++wrongCodes >= settings.maxWrongCodes) {
                        wrongCodes = 0
                        newCode = newPairingCode()
                        code = newCode!!.toByteArray(Charsets.UTF_8)
                        pausedUntilNs = now + settings.wrongCodePauseNs
                    }
                    WRONG
                }
            }
        }
        newCode?.let(onPairingCodeChanged)
        if (verdict == PAUSED) {
            return refuse(client, "too many wrong pairing codes: pairing paused for up to ${settings.wrongCodePauseNs / 1_000_000_000} s", CLOSE_PAUSED)
        }
        if (verdict == WRONG) return refuse(client, "pairing code wrong")
        if (verdict == CONFIRM) {
            // A request the phone would refuse anyway is not put to its user.
            val offered = offer().streams
            request.streams?.firstOrNull { it !in offered }?.let {
                synchronized(codeLock) { client.awaiting = null }
                return refuse(client, "this phone does not capture ${it.key}")
            }
            send(client, StreamMessage.Waiting("the phone asks its user to allow this client"))
            onConfirmationRequested?.invoke(client.info())
            return
        }
        welcome(client, request)
    }

    /**
     * Pairs [id], a client awaiting confirmation ([StreamClientInfo.awaitingConfirmation]), as the phone's user allowed;
     * its address is trusted from now on. False when there is no such client (closed, timed out, answered already).
     */
    public fun allow(id: Long): Boolean {
        val (client, request) = answer(id) ?: return false
        synchronized(codeLock) { trusted += client.address }
        welcome(client, request)
        return true
    }

    /**
     * Closes [id], a client awaiting confirmation, as the phone's user denied it ([CLOSE_DENIED]), and makes a new code
     * (whoever asked knew the code): [onPairingCodeChanged] gets it. False when there is no such client.
     */
    public fun deny(id: Long): Boolean {
        val (client, _) = answer(id) ?: return false
        val newCode = synchronized(codeLock) {
            trusted -= client.address
            newPairingCode().also { code = it.toByteArray(Charsets.UTF_8) }
        }
        onPairingCodeChanged(newCode)
        refuse(client, "denied on the phone", CLOSE_DENIED)
        return true
    }

    /** Takes [id] out of the clients awaiting confirmation, with its request: an answer is given once. */
    private fun answer(id: Long): Pair<Client, StreamMessage.Pair>? = synchronized(unpaired) {
        val client = unpaired.firstOrNull { it.id == id } ?: return null
        val request = synchronized(codeLock) { client.awaiting?.also { client.awaiting = null } } ?: return null
        client to request
    }

    /**
     * Answers a paired client's ping at once (outside the sample queue) with when it came and when the answer leaves,
     * on [sensorClock]; at most one a [MIN_PING_INTERVAL_NS]: a faster client is not answered. Anything else is ignored.
     */
    private fun ping(client: Client, text: String, received: Long) {
        if (!text.startsWith("{\"type\":\"ping\"")) return
        val ping = try {
            StreamCodec.decode(text, "client ${client.address}") as? StreamMessage.Ping ?: return
        } catch (e: DataFormatException) {
            return
        }
        val now = nanoTime()
        if (client.lastPingNs != Long.MIN_VALUE && now - client.lastPingNs < MIN_PING_INTERVAL_NS) return
        client.lastPingNs = now
        ping.laptopClock?.let { client.laptopClock = it.take(MAX_CLOCK_NAME) }
        val previous = client.lastPong
        val previousT4 = ping.previousT4Ns
        if (onClockExchange != null && previous != null && ping.previousId == previous.id && previousT4 != null) {
            val exchange = ClockExchange(previous.t1Ns, previous.t2Ns, previous.t3Ns, previousT4)
            if (exchange.delayNs >= 0) onClockExchange.invoke(client.info(), exchange)
        }
        val pong = StreamMessage.Pong(ping.id, ping.t1Ns, received, sensorClock())
        client.lastPong = pong
        send(client, pong)
        // A frame queued from a thread other than the library's selector can be left unsent when the selector, just
        // done writing the previous one, turns its interest back to reading (Java-WebSocket's write demand races with
        // it). The answer is asked to be written again shortly, when nothing else may follow it for a while.
        pairingWatch.schedule({ demandWrite(client) }, 2, TimeUnit.MILLISECONDS)
    }

    /**
     * A paired client's remote-control command: carried out by [remoteControl] and answered when the phone's user allows
     * it; otherwise answered with the refusal and the connection closed ([CLOSE_NO_REMOTE_CONTROL]). A malformed command
     * is answered as not done, with the reason.
     */
    private fun control(client: Client, text: String) {
        val command = try {
            StreamCodec.decode(text, "client ${client.address}") as? StreamMessage.Control ?: return
        } catch (e: DataFormatException) {
            return send(client, StreamMessage.ControlResult(0, false, e.message ?: "malformed command"))
        }
        val rc = remoteControl
        if (rc == null || !rc.allowed) {
            send(client, StreamMessage.ControlResult(command.id, false, REMOTE_CONTROL_OFF))
            return refuse(client, REMOTE_CONTROL_OFF, CLOSE_NO_REMOTE_CONTROL)
        }
        val outcome = try {
            rc.control(client.info(), command)
        } catch (e: RuntimeException) {
            ControlOutcome("failed on the phone: ${e.message ?: e.javaClass.simpleName}")
        }
        send(client, StreamMessage.ControlResult(command.id, outcome.ok, outcome.reason, outcome.session))
        pairingWatch.schedule({ demandWrite(client) }, 2, TimeUnit.MILLISECONDS)
    }

    /** Asks the library to write what [client]'s connection still holds (see [ping]); also once a second for every client. */
    private fun demandWrite(client: Client) {
        val conn = client.conn
        if (conn.readyState == ReadyState.OPEN && conn.hasBufferedData()) {
            try {
                server.onWriteDemand(conn)
            } catch (_: RuntimeException) {
                // Closed meanwhile.
            }
        }
    }

    private fun send(client: Client, m: StreamMessage) {
        try {
            client.conn.send(StreamCodec.encode(m))
        } catch (_: WebsocketNotConnectedException) {
            // Closed meanwhile.
        }
    }

    /** Admits [client], whose code was right (and which was allowed, when the phone asks): the hello, then its messages. */
    private fun welcome(client: Client, request: StreamMessage.Pair) {
        val offered = offer()
        val streams = request.streams?.filter { it in offered.streams } ?: offered.streams
        request.streams?.firstOrNull { it !in offered.streams }?.let { return refuse(client, "this phone does not capture ${it.key}") }
        // Admission, the hello and the flag under the client's pairing lock: the sender, which takes that lock for a
        // client not yet paired, waits until the hello is queued, so every message published once the client is
        // listed as paired reaches it, and none goes before the hello.
        val admitted = synchronized(client.pairing) {
            val room = synchronized(unpaired) {
                if (clients.count { it.accepted } >= settings.maxClients) {
                    false
                } else {
                    unpaired.remove(client)
                    // [Client.accepted] is set before the hello goes out, so that whoever has received it finds the
                    // client listed as paired.
                    client.accepted = true
                    true
                }
            }
            if (room) {
                client.subscribe(streams, request.rateHz)
                client.conn.send(StreamCodec.encode(StreamMessage.Hello(offered.source, offered.metadata, streams, request.rateHz, clock = true)))
                client.paired = true
            }
            room
        }
        if (!admitted) refuse(client, "too many clients (${settings.maxClients})", CLOSE_TOO_MANY)
    }

    /**
     * Closes the connections that have not finished their upgrade request within
     * [StreamServerSettings.handshakeTimeoutNs] or sent a right code within [StreamServerSettings.pairingTimeoutNs]
     * of their accepted socket; run every second while the server runs (and by tests, with their clock).
     */
    internal fun closeUnpaired() {
        val now = nanoTime()
        val late = ArrayList<Pair<Client, String>>()
        val timedOut = ArrayList<Client>()
        synchronized(unpaired) {
            val i = unpaired.iterator()
            while (i.hasNext()) {
                val c = i.next()
                val age = now - c.acceptedNs
                when {
                    c.conn.readyState == ReadyState.CLOSED -> i.remove()
                    c.conn.readyState == ReadyState.NOT_YET_CONNECTED && age > settings.handshakeTimeoutNs -> {
                        i.remove()
                        late += c to "no WebSocket upgrade within ${settings.handshakeTimeoutNs / 1_000_000_000} s"
                    }
                    c.awaiting != null -> if (now - c.awaitingSinceNs > settings.confirmationTimeoutNs) {
                        // Taken out of waiting under the lock an answer takes, so that a late answer finds nothing.
                        if (synchronized(codeLock) { c.awaiting?.also { c.awaiting = null } } != null) {
                            i.remove()
                            timedOut += c
                        }
                    }
                    age > settings.pairingTimeoutNs -> {
                        i.remove()
                        late += c to "no pairing code within ${settings.pairingTimeoutNs / 1_000_000_000} s"
                    }
                }
            }
        }
        for ((c, reason) in late) drop(c, CLOSE_REFUSED, reason)
        for (c in timedOut) {
            refuse(c, "not allowed on the phone within ${settings.confirmationTimeoutNs / 1_000_000_000} s", CLOSE_NOT_CONFIRMED)
        }
    }

    private val pairingWatch = java.util.concurrent.Executors.newSingleThreadScheduledExecutor { r ->
        Thread(r, "stream-pairing").apply { isDaemon = true }
    }

    private fun refuse(client: Client, reason: String, closeCode: Int = CLOSE_REFUSED) {
        send(client, StreamMessage.Error(reason))
        client.conn.close(closeCode, reason.take(100))
    }

    /**
     * The socket as the library reads it: a connection that has not paired may send at most
     * [StreamServerSettings.maxUnpairedBytes] (the upgrade request and the pair message); beyond that it reads as
     * closed, which closes the connection.
     */
    private inner class Limited(private val channel: SocketChannel, private val key: SelectionKey) : ByteChannel {
        private var read = 0L

        override fun read(dst: ByteBuffer): Int {
            val client = (key.attachment() as? WebSocketImpl)?.getAttachment<Client>()
            if (client != null && client.accepted) return channel.read(dst)
            if (read >= settings.maxUnpairedBytes) return -1
            val n = channel.read(dst)
            if (n > 0) read += n
            return if (read > settings.maxUnpairedBytes) -1 else n
        }

        override fun write(src: ByteBuffer): Int = channel.write(src)

        override fun isOpen(): Boolean = channel.isOpen

        override fun close() = channel.close()
    }

    /** The sender thread's [StringBuilder], for encoding. */
    private val sb = StringBuilder(256)

    /** Sender thread ([handOff]): [m], sampled at [t], encoded once for every paired client that asked for it and is due. */
    private fun sendToClients(m: StreamMessage, t: Long) {
        val stream = if (m is StreamMessage.Sample) m.stream else SessionStream.ORIENTATION
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

    private inner class Client(val conn: WebSocketImpl, val acceptedNs: Long) {
        val id = nextId.incrementAndGet()

        /** The peer's address, known once its upgrade is done. */
        @Volatile var address: String = "?"

        /** The name given in its pair message, cleaned. */
        @Volatile var name: String? = null

        /** Its request, while the phone's user has not answered it; set and taken under [codeLock]. */
        @Volatile var awaiting: StreamMessage.Pair? = null

        /** When [awaiting] was set, on [nanoTime]. */
        @Volatile var awaitingSinceNs = 0L

        /** Held while the hello is queued and [paired] set. */
        val pairing = Any()

        /** The code was right: set just before the hello is queued (what [info] reports as paired). */
        @Volatile var accepted = false

        /** The hello is queued: the sender may send this client messages. */
        @Volatile var paired = false

        /** The clock its pings name. */
        @Volatile var laptopClock: String? = null

        /** When its last ping was answered, on [nanoTime]; the answer itself (the phone's half of the exchange). */
        var lastPingNs = Long.MIN_VALUE
        var lastPong: StreamMessage.Pong? = null
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
            droppedHandOffAtPairing = handOff.droppedCount
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
                val lost = dropped + (handOff.droppedCount - droppedHandOffAtPairing)
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
            id = id, name = name, awaitingConfirmation = awaiting != null, laptopClock = laptopClock,
        )
    }

    public companion object {
        /** A client's pings are answered at most once per 10 ms (a client pings 4 times a second). */
        public const val MIN_PING_INTERVAL_NS: Long = 10_000_000

        /** Close codes (4000–4999 are the application's; docs/STREAMING.md): a refused request (wrong code, malformed, binary, too late). */
        public const val CLOSE_REFUSED: Int = 4001

        /** Not from the local network. */
        public const val CLOSE_NOT_LOCAL: Int = 4003

        /** Pairing paused after too many wrong codes (a new code is shown). */
        public const val CLOSE_PAUSED: Int = 4029

        /** The phone's user denied the client (a new code is shown). */
        public const val CLOSE_DENIED: Int = 4010

        /** The phone's user did not answer within [StreamServerSettings.confirmationTimeoutNs]. */
        public const val CLOSE_NOT_CONFIRMED: Int = 4011

        private const val RIGHT = 0
        private const val WRONG = 1
        private const val PAUSED = 2
        private const val CONFIRM = 3

        /** A client's name as the phone shows it: no control characters, at most 40 characters. */
        private fun cleanName(name: String): String? =
            name.filter { !it.isISOControl() && Character.getType(it) != Character.FORMAT.toInt() }.trim().take(40).ifEmpty { null }

        /** A remote-control command while the phone's user does not allow remote control (or the phone has none). */
        public const val CLOSE_NO_REMOTE_CONTROL: Int = 4013

        /** The refusal of a command while remote control is off. */
        public const val REMOTE_CONTROL_OFF: String = "remote control is off on the phone (the Stream screen's switch)"

        /** The longest clock name taken from a ping. */
        private const val MAX_CLOCK_NAME = 200

        private const val CONTROL_PREFIX = "{\"type\":\"control\""

        /** Too many paired clients, or an unpaired connection closed to make room for a newer one. */
        public const val CLOSE_TOO_MANY: Int = 4008

        /** The library's ping interval, in s: a client that answers none for 1.5 times this is closed as lost. */
        public const val CONNECTION_LOST_TIMEOUT_S: Int = 10

        private val random = SecureRandom()

        /** A new 6-digit pairing code (SecureRandom). */
        @JvmStatic
        public fun randomPairingCode(): String = String.format(Locale.ROOT, "%06d", random.nextInt(1_000_000))

        /** Loopback, link-local, site-local (10/8, 172.16/12, 192.168/16) or IPv6 unique-local (fc00::/7). */
        @JvmStatic
        public fun isLocalNetwork(a: InetAddress): Boolean =
            a.isLoopbackAddress || a.isLinkLocalAddress || a.isSiteLocalAddress ||
                (a is Inet6Address && (a.address[0].toInt() and 0xfe) == 0xfc)
    }
}
