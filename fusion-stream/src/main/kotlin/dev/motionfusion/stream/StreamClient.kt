package dev.motionfusion.stream

import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import org.java_websocket.client.WebSocketClient
import org.java_websocket.drafts.Draft_6455
import org.java_websocket.framing.CloseFrame
import org.java_websocket.protocols.IProtocol
import org.java_websocket.protocols.Protocol
import org.java_websocket.handshake.ServerHandshake
import java.io.IOException
import java.net.URI
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/** How a [StreamClient]'s connection ended. */
public enum class StreamEnd {
    /** The phone closed it (streaming turned off). */
    PHONE_STOPPED,

    /** Lost: no close from the phone (a reset, the phone's process gone), or no pong within the ping timeout. */
    LOST,

    /** A message from the phone was over [StreamClient.MAX_MESSAGE_BYTES]. */
    TOO_LARGE,

    /** The phone refused the pairing, or ended the connection with another code. */
    REFUSED,

    /** The phone's user denied this client, or did not answer in time ([StreamServer.CLOSE_DENIED], [StreamServer.CLOSE_NOT_CONFIRMED]). */
    DENIED,

    /** This side closed it. */
    CLOSED,
}

/**
 * The laptop side of the live stream: connects to a phone's [StreamServer] at [uri], pairs with
 * [request], gives the hello to [onHello] and then every later message to [onMessage], in order, on
 * the connection's reading thread (so [onHello] has returned before the first sample is handed on). A slow [onMessage] slows the reading, and the phone then drops messages for this
 * client (it says how many in its status messages). A malformed message after the hello is skipped and its reason
 * given to [onMalformed]; a message over [MAX_MESSAGE_BYTES] ends the connection ([StreamEnd.TOO_LARGE]) before it is
 * read into memory. The ping timeout is the server's ([StreamServer.CONNECTION_LOST_TIMEOUT_S]): a phone that went
 * silent is found lost within 10–20 s.
 */
public class StreamClient @JvmOverloads constructor(
    private val uri: URI,
    private val request: StreamMessage.Pair,
    private val onHello: (StreamMessage.Hello) -> Unit = {},
    private val onMalformed: (String) -> Unit = {},
    private val onMessage: (StreamMessage) -> Unit,
) : AutoCloseable {
    private val helloLatch = CountDownLatch(1)
    private val closedLatch = CountDownLatch(1)

    @Volatile private var helloMessage: StreamMessage.Hello? = null

    @Volatile private var failure: String? = null

    @Volatile private var helloFailure: Exception? = null

    @Volatile private var closeReason: String? = null

    @Volatile private var ended: StreamEnd? = null

    @Volatile private var closing = false

    /** What the phone waits for before its hello (its user's answer), once it said so. */
    @Volatile private var waiting: String? = null

    @Volatile private var onWaiting: (String) -> Unit = {}

    private val socket = object : WebSocketClient(uri, Draft_6455(emptyList(), listOf<IProtocol>(Protocol("")), MAX_MESSAGE_BYTES)) {
        override fun onOpen(handshake: ServerHandshake) = send(StreamCodec.encode(request))

        override fun onMessage(message: String) {
            val m = try {
                StreamCodec.decode(message, uri.toString())
            } catch (e: DataFormatException) {
                if (helloMessage != null) return onMalformed(e.message ?: "malformed message")
                fail(e.message ?: "malformed message")
                close(CLOSE_MALFORMED, "malformed message")
                return
            }
            when {
                m is StreamMessage.Error -> fail("the phone refused: ${m.reason}")
                helloMessage == null && m is StreamMessage.Waiting -> {
                    waiting = m.reason
                    onWaiting(m.reason)
                }
                helloMessage == null && m is StreamMessage.Hello -> {
                    try {
                        onHello(m)
                        helloMessage = m
                    } catch (e: Exception) {
                        helloFailure = e
                        close()
                    }
                    helloLatch.countDown()
                }
                helloMessage == null -> {
                    fail("the phone sent ${m::class.simpleName} before hello")
                    close(CLOSE_MALFORMED, "no hello")
                }
                else -> this@StreamClient.onMessage(m)
            }
        }

        override fun onClose(code: Int, reason: String?, remote: Boolean) {
            ended = when {
                code == CloseFrame.TOOBIG && !remote -> StreamEnd.TOO_LARGE
                closing && !remote -> StreamEnd.CLOSED
                code == CloseFrame.ABNORMAL_CLOSE || code == CloseFrame.NEVER_CONNECTED -> StreamEnd.LOST
                remote && (code == CloseFrame.NORMAL || code == CloseFrame.GOING_AWAY) -> StreamEnd.PHONE_STOPPED
                remote && (code == StreamServer.CLOSE_DENIED || code == StreamServer.CLOSE_NOT_CONFIRMED) -> StreamEnd.DENIED
                else -> StreamEnd.REFUSED
            }
            val why = when (ended) {
                StreamEnd.TOO_LARGE -> "a message from the phone is over the limit of ${MAX_MESSAGE_BYTES shr 20} MiB"
                StreamEnd.LOST -> "connection lost${(failure ?: reason).let { if (it.isNullOrEmpty()) "" else ": $it" }}"
                else -> null
            }
            if (failure == null && helloMessage == null) fail(why ?: "connection closed before hello ($code${if (reason.isNullOrEmpty()) "" else ": $reason"})")
            closeReason = why ?: if (reason.isNullOrEmpty()) "closed ($code)" else reason
            helloLatch.countDown()
            closedLatch.countDown()
        }

        override fun onClosing(code: Int, reason: String?, remote: Boolean) {
            // Over the size limit: the rest of that frame is not waited for (nor a phone's answer to the close).
            if (code == CloseFrame.TOOBIG && !remote) closeConnection(code, reason ?: "message too big")
        }

        override fun onError(ex: Exception) {
            fail(describe(ex))
        }
    }.apply {
        isTcpNoDelay = true
        connectionLostTimeout = StreamServer.CONNECTION_LOST_TIMEOUT_S
    }

    private fun fail(reason: String) {
        if (failure == null) failure = reason
        helloLatch.countDown()
    }

    /**
     * Connects and pairs; returns the phone's hello. When the phone says it asks its user to allow this client (a
     * `waiting` message), [onWaiting] gets its reason (on the connection's thread) and the hello is awaited for up to
     * [confirmationTimeoutMs] more; the phone closes the request itself when its user does not answer
     * ([StreamEnd.DENIED]). @throws IOException when it cannot connect, is refused or denied, or hears no hello in time;
     * what [onHello] threw, as it is.
     */
    @JvmOverloads
    public fun connect(timeoutMs: Long = 10_000, confirmationTimeoutMs: Long = CONFIRMATION_WAIT_MS, onWaiting: (String) -> Unit = {}): StreamMessage.Hello {
        this.onWaiting = onWaiting
        socket.connect()
        if (!helloLatch.await(timeoutMs, TimeUnit.MILLISECONDS) &&
            (waiting == null || !helloLatch.await(confirmationTimeoutMs, TimeUnit.MILLISECONDS))
        ) {
            socket.close()
            throw IOException(
                if (waiting == null) "$uri: no answer within ${timeoutMs / 1000.0} s"
                else "$uri: not allowed on the phone within ${(timeoutMs + confirmationTimeoutMs) / 1000.0} s",
            )
        }
        helloMessage?.let { return it }
        // Refused: the phone closes right after its error; its close code tells a denial from other refusals ([end]).
        closedLatch.await(REFUSAL_CLOSE_MS, TimeUnit.MILLISECONDS)
        socket.close()
        helloFailure?.let { throw it }
        throw IOException("$uri: ${failure ?: "no hello"}")
    }

    /**
     * Sends a clock [ping] (docs/SYNC.md; only after a hello whose `clock` is true: older phones do not answer it); its
     * [StreamMessage.Pong] reaches onMessage. Returns false when the connection is not open.
     */
    public fun send(ping: StreamMessage.Ping): Boolean = send(ping as StreamMessage)

    /**
     * Sends a client's [message] after the hello: a [StreamMessage.Ping] or a remote-control [StreamMessage.Control]
     * (answered by a [StreamMessage.ControlResult] to onMessage). Returns false when the connection is not open.
     */
    public fun send(message: StreamMessage): Boolean = try {
        socket.send(StreamCodec.encode(message))
        true
    } catch (_: org.java_websocket.exceptions.WebsocketNotConnectedException) {
        false
    }

    /** Waits until the phone closes the connection or [timeoutMs] passes; true when it closed. */
    public fun awaitClose(timeoutMs: Long): Boolean = closedLatch.await(timeoutMs, TimeUnit.MILLISECONDS)

    /** Why the connection ended (the phone's reason, or an error), null while it is open. */
    public val endReason: String? get() = if (ended == StreamEnd.LOST || ended == StreamEnd.TOO_LARGE) closeReason else failure ?: closeReason

    /** How the connection ended, null while it is open. */
    public val end: StreamEnd? get() = ended

    override fun close() {
        closing = true
        socket.closeBlocking()
    }

    public companion object {
        /** The largest message taken from the phone (its hello with the metadata is a few kB). */
        public const val MAX_MESSAGE_BYTES: Int = 1 shl 20

        /** How long [connect] waits for the hello once the phone asks its user (its own limit is 60 s). */
        public const val CONFIRMATION_WAIT_MS: Long = 120_000

        private const val CLOSE_MALFORMED = 4002

        /** How long a refused [connect] waits for the phone's close, which says how it ended. */
        private const val REFUSAL_CLOSE_MS = 2_000L
    }
}

/** A connection failure in words: what a user can act on, not the exception's class name. */
internal fun describe(ex: Exception): String = when (ex) {
    is java.net.ConnectException -> "nothing listening at that address and port (${ex.message ?: "connection refused"}): is the phone's stream on, and are they the ones it shows?"
    is java.net.UnknownHostException -> "unknown host ${ex.message ?: ""}: check the address the phone shows"
    is java.net.SocketTimeoutException -> "no answer in time (${ex.message ?: "timed out"}): is the phone on the same network?"
    is java.net.NoRouteToHostException -> "no route to the phone (${ex.message ?: ""}): is it on the same network?"
    else -> ex.message ?: ex.javaClass.simpleName
}
