package dev.motionfusion.app.stream

import dev.motionfusion.app.live.Capture
import dev.motionfusion.app.live.OrientationListener
import dev.motionfusion.app.live.RawListener
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.stream.StreamClientInfo
import dev.motionfusion.stream.StreamOffer
import dev.motionfusion.stream.StreamServer
import dev.motionfusion.stream.StreamServerSettings
import java.io.IOException
import java.net.Inet4Address
import java.net.InetSocketAddress
import java.net.NetworkInterface
import java.security.SecureRandom
import java.util.concurrent.Executor
import java.util.concurrent.Executors
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

    /** The server is being started, off the main thread. */
    data object Starting : StreamState

    /**
     * Listening on [port] of every interface; [addresses] are the phone's site-local IPv4 addresses. A client
     * whose [StreamClientInfo.stalled] is true does not keep up: its messages are being dropped.
     */
    data class On(val addresses: List<String>, val port: Int, val code: String, val clients: List<StreamClientInfo>) : StreamState

    /** The server is closing its connections, off the main thread. */
    data object Stopping : StreamState

    /** The server could not start (the port taken), or the system refused the foreground service that keeps it going. */
    data class Failed(val reason: String) : StreamState
}

/**
 * The phone side of the live stream (docs/STREAMING.md): [start] makes a pairing code and starts a
 * [StreamServer] on [port] of every interface (the server refuses peers outside the local network
 * and USB) on the [control] executor, then holds the [capture] as the live screen does and hands the
 * server every raw event and the live filter's orientation after each step, on the capture thread;
 * [stop] lets go of the capture at once and closes the server on [control]. The main thread never
 * waits for a socket: [state] goes through [StreamState.Starting] and [StreamState.Stopping]. [start]
 * also asks [keepAlive] for the foreground service that keeps streaming going with the screen off
 * (StreamService), which follows [state] and ends itself when it is off. [state] is refreshed about
 * once a second while on. [start] and [stop] are called on [scope]'s thread (the main thread), and the
 * controller's own steps come back to it there.
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
    /** Where the server binds its socket and closes its connections (up to [STOP_TIMEOUT_MS]); one thread, in order. */
    private val control: Executor = Executors.newSingleThreadExecutor { r -> Thread(r, "stream-control").apply { isDaemon = true } },
    private val serverSettings: StreamServerSettings = StreamServerSettings(),
    /** Starts the foreground service that keeps the stream going; returns why the system refused, or null. */
    private val keepAlive: () -> String? = { null },
) {
    private val stateFlow = MutableStateFlow<StreamState>(StreamState.Off)
    val state: StateFlow<StreamState> = stateFlow.asStateFlow()

    /** The server being started, until it runs (or [stop] gave it up). */
    private var starting: StreamServer? = null
    private var running: Running? = null
    /** A server is being stopped: [start] waits for [StreamState.Off]. */
    private var stopping = false

    private class Running(val server: StreamServer, val code: String, val raw: RawListener, val oriented: OrientationListener, val refresh: Job)

    /** Starting, on, or stopping: something may listen. */
    val isOn: Boolean get() = running != null || starting != null || stopping

    fun start() {
        if (isOn) return
        val code = String.format(java.util.Locale.ROOT, "%06d", random.nextInt(1_000_000))
        val server = StreamServer(InetSocketAddress(port), code, {
            val m = metadata()
            StreamOffer(m.source, m, (capture.streams + SessionStream.ORIENTATION).toList())
        }, serverSettings)
        starting = server
        stateFlow.value = StreamState.Starting
        keepAlive()?.let { reason ->
            starting = null
            stateFlow.value = StreamState.Failed(reason)
            return
        }
        control.execute {
            val failure = try {
                server.start()
                null
            } catch (e: IOException) {
                e.message ?: e.javaClass.simpleName
            }
            scope.launch { started(server, code, failure) }
        }
    }

    /** Back on the main thread: the server listens (or could not). Given up meanwhile ([stop]): nothing more to do here. */
    private fun started(server: StreamServer, code: String, failure: String?) {
        if (starting !== server) return
        starting = null
        if (failure != null) {
            stateFlow.value = StreamState.Failed(failure)
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

    /**
     * Stops streaming: the capture is let go at once, the server closed on [control]; then [StreamState.Off],
     * or [StreamState.Failed] with [failure] (the foreground service was refused).
     */
    fun stop(failure: String? = null) {
        val server = running?.let { r ->
            running = null
            r.refresh.cancel()
            capture.unlisten(r.raw)
            capture.unlisten(r.oriented)
            capture.release(onScreen = true)
            r.server
        } ?: starting?.also { starting = null } // closed after its start, in the control executor's order
        if (server == null) {
            if (failure != null && !stopping) stateFlow.value = StreamState.Failed(failure)
            return
        }
        stopping = true
        stateFlow.value = StreamState.Stopping
        control.execute {
            try {
                server.stop(STOP_TIMEOUT_MS)
            } catch (_: Exception) {
                // A server that never started has nothing to close.
            }
            scope.launch {
                stopping = false
                stateFlow.value = if (failure != null) StreamState.Failed(failure) else StreamState.Off
            }
        }
    }

    companion object {
        const val PORT = 8765
        const val STOP_TIMEOUT_MS = 500
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
