package dev.motionfusion.app.stream

import dev.motionfusion.app.live.Capture
import dev.motionfusion.app.live.OrientationListener
import dev.motionfusion.app.live.RawListener
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.stream.StreamClientInfo
import dev.motionfusion.stream.StreamOffer
import dev.motionfusion.stream.StreamServer
import java.io.IOException
import java.net.Inet4Address
import java.net.InetSocketAddress
import java.net.NetworkInterface
import java.security.SecureRandom
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Job
import kotlinx.coroutines.delay
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.isActive
import kotlinx.coroutines.launch

/** What the Stream screen shows. */
internal sealed interface StreamState {
    /** Nothing listens. */
    data object Off : StreamState

    /** Listening on [port] of every interface; [addresses] are the phone's site-local IPv4 addresses. */
    data class On(val addresses: List<String>, val port: Int, val code: String, val clients: List<StreamClientInfo>) : StreamState

    /** The server could not start (the port taken). */
    data class Failed(val reason: String) : StreamState
}

/**
 * The phone side of the live stream (docs/STREAMING.md): [start] makes a pairing code, starts a
 * [StreamServer] on [port] of every interface (the server refuses peers outside the local network
 * and USB), holds the [capture] as the live screen does, and hands the server every raw event and
 * the live filter's orientation after each step, on the capture thread; [stop] undoes all. [state]
 * is refreshed about once a second while on. [start] and [stop] are called on the main thread.
 */
internal class StreamController(
    private val capture: Capture,
    /** The session metadata as a recording started now would write it (RecordingMetadata), for the hello. */
    private val metadata: () -> SessionMetadata,
    private val scope: CoroutineScope,
    private val port: Int = PORT,
    private val addresses: () -> List<String> = ::siteLocalAddresses,
    private val random: SecureRandom = SecureRandom(),
    private val refreshMs: Long = 1000L,
) {
    private val stateFlow = MutableStateFlow<StreamState>(StreamState.Off)
    val state: StateFlow<StreamState> = stateFlow.asStateFlow()

    private var running: Running? = null

    private class Running(val server: StreamServer, val code: String, val raw: RawListener, val oriented: OrientationListener, val refresh: Job)

    val isOn: Boolean get() = running != null

    fun start() {
        if (running != null) return
        val code = String.format(java.util.Locale.ROOT, "%06d", random.nextInt(1_000_000))
        val server = StreamServer(InetSocketAddress(port), code, {
            val m = metadata()
            StreamOffer(m.source, m, (capture.streams + SessionStream.ORIENTATION).toList())
        })
        try {
            server.start()
        } catch (e: IOException) {
            stateFlow.value = StreamState.Failed(e.message ?: e.javaClass.simpleName)
            return
        }
        val scratch = FloatArray(MAX_VALUES)
        val raw = RawListener { stream, t, accuracy, values, offset ->
            values.copyInto(scratch, 0, offset, offset + stream.valueCount)
            server.publishSample(stream, t, scratch, accuracy)
        }
        val oriented = OrientationListener { t, qw, qx, qy, qz -> server.publishOrientation(t, qw, qx, qy, qz) }
        // As a screen: the capture thread takes a batch every 10 ms rather than every 100 ms (the stream's latency).
        capture.acquire(onScreen = true)
        capture.listen(raw)
        capture.listen(oriented)
        val refresh = scope.launch {
            while (isActive) {
                stateFlow.value = StreamState.On(addresses(), server.port, code, server.clients())
                delay(refreshMs)
            }
        }
        running = Running(server, code, raw, oriented, refresh)
        stateFlow.value = StreamState.On(addresses(), server.port, code, server.clients())
    }

    fun stop() {
        val r = running ?: return
        running = null
        r.refresh.cancel()
        capture.unlisten(r.raw)
        capture.unlisten(r.oriented)
        capture.release(onScreen = true)
        r.server.stop(STOP_TIMEOUT_MS)
        stateFlow.value = StreamState.Off
    }

    /** Implemented by the application: the one controller. */
    interface Provider {
        val streamController: StreamController
    }

    companion object {
        const val PORT = 8765
        private const val STOP_TIMEOUT_MS = 500
        private val MAX_VALUES = SessionStream.entries.maxOf { it.valueCount }

        /** The phone's site-local IPv4 addresses (Wi-Fi, hotspot, Ethernet), those a laptop on the same network reaches. */
        fun siteLocalAddresses(): List<String> = try {
            NetworkInterface.getNetworkInterfaces()?.toList().orEmpty()
                .filter { it.isUp && !it.isLoopback }
                .flatMap { it.inetAddresses.toList() }
                .filter { it is Inet4Address && it.isSiteLocalAddress }
                .mapNotNull { it.hostAddress }
                .distinct()
        } catch (_: Exception) {
            emptyList()
        }
    }
}
