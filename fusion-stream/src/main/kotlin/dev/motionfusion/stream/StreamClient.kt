package dev.motionfusion.stream

import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import org.java_websocket.client.WebSocketClient
import org.java_websocket.handshake.ServerHandshake
import java.io.IOException
import java.net.URI
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * The laptop side of the live stream: connects to a phone's [StreamServer] at [uri], pairs with
 * [request], gives the hello to [onHello] and then every later message to [onMessage], in order, on
 * the connection's reading thread (so [onHello] has returned before the first sample is handed on). A slow [onMessage] slows the reading, and the phone then drops messages for this
 * client (it says how many in its status messages).
 */
public class StreamClient @JvmOverloads constructor(
    private val uri: URI,
    private val request: StreamMessage.Pair,
    private val onHello: (StreamMessage.Hello) -> Unit = {},
    private val onMessage: (StreamMessage) -> Unit,
) : AutoCloseable {
    private val helloLatch = CountDownLatch(1)
    private val closedLatch = CountDownLatch(1)

    @Volatile private var helloMessage: StreamMessage.Hello? = null

    @Volatile private var failure: String? = null

    @Volatile private var helloFailure: Exception? = null

    @Volatile private var closeReason: String? = null

    private val socket = object : WebSocketClient(uri) {
        override fun onOpen(handshake: ServerHandshake) = send(StreamCodec.encode(request))

        override fun onMessage(message: String) {
            val m = try {
                StreamCodec.decode(message, uri.toString())
            } catch (e: DataFormatException) {
                fail(e.message ?: "malformed message")
                close(CLOSE_MALFORMED, "malformed message")
                return
            }
            when {
                m is StreamMessage.Error -> fail("the phone refused: ${m.reason}")
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
            if (failure == null && helloMessage == null) fail("connection closed before hello ($code${if (reason.isNullOrEmpty()) "" else ": $reason"})")
            closeReason = if (reason.isNullOrEmpty()) "closed ($code)" else reason
            helloLatch.countDown()
            closedLatch.countDown()
        }

        override fun onError(ex: Exception) {
            fail("${ex.javaClass.simpleName}: ${ex.message ?: "connection failed"}")
        }
    }.apply { isTcpNoDelay = true }

    private fun fail(reason: String) {
        if (failure == null) failure = reason
        helloLatch.countDown()
    }

    /**
     * Connects and pairs; returns the phone's hello. @throws IOException when it cannot connect, is refused, or hears no
     * hello within [timeoutMs]; what [onHello] threw, as it is.
     */
    public fun connect(timeoutMs: Long = 10_000): StreamMessage.Hello {
        socket.connect()
        if (!helloLatch.await(timeoutMs, TimeUnit.MILLISECONDS)) {
            socket.close()
            throw IOException("$uri: no answer within ${timeoutMs / 1000.0} s")
        }
        helloMessage?.let { return it }
        socket.close()
        helloFailure?.let { throw it }
        throw IOException("$uri: ${failure ?: "no hello"}")
    }

    /** Waits until the phone closes the connection or [timeoutMs] passes; true when it closed. */
    public fun awaitClose(timeoutMs: Long): Boolean = closedLatch.await(timeoutMs, TimeUnit.MILLISECONDS)

    /** Why the connection ended (the phone's reason, or an error), null while it is open. */
    public val endReason: String? get() = failure ?: closeReason

    override fun close() {
        socket.closeBlocking()
    }

    private companion object {
        const val CLOSE_MALFORMED = 4002
    }
}
