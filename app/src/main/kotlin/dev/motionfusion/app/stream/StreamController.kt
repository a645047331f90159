package dev.motionfusion.app.stream

import androidx.annotation.StringRes
import dev.motionfusion.app.fusion.Capture
import dev.motionfusion.app.fusion.OrientationListener
import dev.motionfusion.app.fusion.RawListener
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.RemoteStart
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.core.sync.ClockExchange
import dev.motionfusion.stream.ControlOutcome
import dev.motionfusion.stream.RemoteControl
import dev.motionfusion.stream.StreamClientInfo
import dev.motionfusion.stream.StreamOffer
import dev.motionfusion.stream.StreamServer
import dev.motionfusion.stream.StreamServerSettings
import dev.motionfusion.stream.UdpPush
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
    data class On(
        val addresses: List<String>,
        val port: Int,
        val code: String,
        val clients: List<StreamClientInfo>,
        /** The UDP push, when the user asked for one. */
        val udp: UdpView? = null,
        /** The laptop that sent the last remote-control command while allowed ("fusion record on lab-laptop (192.168.1.20)"), or null. */
        val controlledBy: String? = null,
    ) : StreamState

    /** The server is closing its connections, off the main thread. */
    data object Stopping : StreamState

    /**
     * The server could not start (the port taken), stopped by itself, or the system refused the foreground service
     * that keeps it going: [text], a string resource saying what failed and what to do ([StreamFailure], a
     * foreground refusal's); the technical detail is in the log.
     */
    data class Failed(@StringRes val text: Int) : StreamState
}

/** The UDP push (docs/STREAMING.md, "UDP push") as the Stream screen shows it. */
internal sealed interface UdpView {
    val target: String

    /** The target being resolved and the socket opened, off the main thread. */
    data class Starting(override val target: String) : UdpView

    /** Pushing: messages [sent], and [dropped] (its queue full, or a datagram the system would not send). */
    data class Pushing(override val target: String, val sent: Long, val dropped: Long) : UdpView

    /** Not started: [text] says why ([StreamFailure]), or null when [target] is not `host:port`. */
    data class Failed(override val target: String, @StringRes val text: Int?) : UdpView
}

/**
 * What the phone does for a laptop in control (docs/STREAMING.md, "Remote control"): the recording service, as if Record,
 * Stop or a marker were pressed. Called on the server's connection threads; each returns null when done, else why not.
 */
internal interface RemoteRecording {
    /** Starts a recording tagged with [start] (meta.json's remote_start; no sample before its instant). */
    fun start(start: RemoteStart): String?

    fun stop(): String?

    /** A marker at [atNs] (sensor clock) with [label]. */
    fun mark(atNs: Long, label: String): String?

    /** A whole clock exchange with the laptop clock [laptopClock]: into the clock.csv of the recording running now, if any. */
    fun clockExchange(e: ClockExchange, laptopClock: String)

    companion object {
        /** No recording here (tests of the stream alone). */
        val NONE = object : RemoteRecording {
            override fun start(start: RemoteStart) = "recording is not available"
            override fun stop() = "recording is not available"
            override fun mark(atNs: Long, label: String) = "recording is not available"
            override fun clockExchange(e: ClockExchange, laptopClock: String) = Unit
        }
    }
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
 * once a second while on. While on, [pushUdp] also sends every message to a host and port on the local
 * network ([UdpPush]), set up on [lookup] (the name is resolved there, so that a slow lookup never holds up a
 * stop on [control]). [start], [stop], [pushUdp] and
 * [stopUdp] are called on [scope]'s thread (the main thread), and the controller's own steps come back to
 * it there.
 *
 * A laptop that gives the right code is not let in yet: the server holds it until the user answers on the screen or in
 * the notification ([StreamClientInfo.awaitingConfirmation]; [allow], [deny]); the state is refreshed at once when one
 * asks. An address allowed once pairs again without asking until streaming is turned off; a deny makes a new code.
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
    /** Starts the foreground service that keeps the stream going; returns why the system refused (a string resource), or null. */
    private val keepAlive: () -> Int? = { null },
    /** Where a UDP push's target is looked up and its socket opened: a thread of its own for each push. */
    private val lookup: Executor = LOOKUP,
    /** Where the technical detail of a failure goes (the app's log); the screen shows a [StreamFailure]'s text. */
    private val log: (String, Throwable?) -> Unit = { _, _ -> },
    /** The recording a laptop in control starts, stops and marks, and which keeps the clock exchanges. */
    private val recording: RemoteRecording = RemoteRecording.NONE,
    /** The sensor clock (elapsedRealtimeNanos), which the clock exchanges report. */
    private val sensorClock: () -> Long = System::nanoTime,
) {
    private val stateFlow = MutableStateFlow<StreamState>(StreamState.Off)
    val state: StateFlow<StreamState> = stateFlow.asStateFlow()

    /** The server being started, until it runs (or [stop] gave it up). */
    private var starting: StreamServer? = null
    private var running: Running? = null
    /** A server is being stopped: [start] waits for [StreamState.Off]. */
    private var stopping = false

    /** The UDP push, read by the capture thread. */
    @Volatile private var udp: UdpPush? = null
    /** What the screen shows of the UDP push while [udp] is not running (starting, failed). */
    private var udpView: UdpView? = null
    /** Counts requests of the UDP push: a set-up that finishes after a later request is given up. */
    private var udpRequest = 0

    private val offerNow = {
        val m = metadata()
        StreamOffer(m.source, m, (capture.streams + SessionStream.ORIENTATION).toList())
    }

    /** Whether the user allows a laptop to start, stop and mark recordings (the screen's switch; off by default). */
    @Volatile var remoteControlAllowed: Boolean = false
        private set

    /** Who sent the last remote-control command while allowed; cleared when streaming stops or remote control is turned off. */
    @Volatile private var controlledBy: String? = null

    /** The switch "Allow remote control": on, a paired laptop may start, stop and mark recordings; off, its commands are refused. */
    fun allowRemoteControl(on: Boolean) {
        remoteControlAllowed = on
        if (!on) controlledBy = null
        showNow()
    }

    private val remoteControl = object : RemoteControl {
        override val allowed: Boolean get() = remoteControlAllowed

        override fun control(client: StreamClientInfo, command: StreamMessage.Control): ControlOutcome {
            val by = client.name ?: client.address
            val reason = when (command.command) {
                StreamMessage.Control.Command.START ->
                    recording.start(RemoteStart(by, command.laptopClock, command.laptopNs, command.atNs ?: sensorClock()))
                StreamMessage.Control.Command.STOP -> recording.stop()
                StreamMessage.Control.Command.MARK -> recording.mark(command.atNs ?: sensorClock(), command.label ?: "")
            }
            // In control from its first command while allowed, whatever the recording made of it.
            controlledBy = "$by (${client.address})"
            scope.launch { showNow() }
            return ControlOutcome(reason)
        }
    }

    private class Running(val server: StreamServer, val raw: RawListener, val oriented: OrientationListener, val refresh: Job)

    /** Starting, on, or stopping: something may listen. */
    val isOn: Boolean get() = running != null || starting != null || stopping

    fun start() {
        if (isOn) return
        val code = newCode()
        lateinit var server: StreamServer
        server = StreamServer(
            InetSocketAddress(port), code, offerNow, serverSettings,
            newPairingCode = ::newCode,
            // After too many wrong codes the server makes a new one: shown at once.
            onPairingCodeChanged = { scope.launch { if (running?.server === server) showNow() } },
            // A server that died (out of memory, say) is not shown as on.
            onFailure = { reason ->
                scope.launch {
                    if (running?.server === server) {
                        log("the stream server stopped: $reason", null)
                        stop(failure = StreamFailure.SERVER_STOPPED.text)
                    }
                }
            },
            // A laptop with the right code asks to connect: shown at once (screen and notification) for the user to answer.
            onConfirmationRequested = { scope.launch { if (running?.server === server) showNow() } },
            sensorClock = sensorClock,
            // A recording running while linked keeps the exchanges of the laptop its pings name.
            onClockExchange = { client, e -> client.laptopClock?.let { recording.clockExchange(e, it) } },
            remoteControl = remoteControl,
        )
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
                log("cannot start the stream server", e)
                StreamFailure.of(e).text
            }
            scope.launch { started(server, failure) }
        }
    }

    /** Back on the main thread: the server listens (or could not). Given up meanwhile ([stop]): nothing more to do here. */
    private fun started(server: StreamServer, @StringRes failure: Int?) {
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
            udp?.publishSample(stream, t, scratch, accuracy)
        }
        val oriented = OrientationListener { t, qw, qx, qy, qz ->
            server.publishOrientation(t, qw, qx, qy, qz)
            udp?.publishOrientation(t, qw, qx, qy, qz)
        }
        // As a screen: the capture thread takes a batch every 10 ms rather than every 100 ms (the stream's latency).
        capture.acquire(onScreen = true)
        capture.listen(raw)
        capture.listen(oriented)
        val refresh = scope.launch {
            while (isActive) {
                stateFlow.value = on(server)
                delay(refreshMs)
            }
        }
        running = Running(server, raw, oriented, refresh)
        stateFlow.value = on(server)
    }

    private fun newCode() = String.format(java.util.Locale.ROOT, "%06d", random.nextInt(1_000_000))

    /** The code is the server's: a new one after too many wrong codes. */
    private fun on(server: StreamServer) = StreamState.On(
        addresses(), server.port, server.pairingCode, server.clients(),
        udp?.let { UdpView.Pushing(it.target.let { a -> "${a.hostString}:${a.port}" }, it.sent, it.droppedCount) } ?: udpView,
        controlledBy,
    )

    private fun showNow() {
        running?.let { stateFlow.value = on(it.server) }
    }

    /** The user allowed the laptop [id] that asks to connect: it pairs (on [control]), and the state shows it. */
    fun allow(id: Long) = answer(id) { it.allow(id) }

    /** The user denied the laptop [id]: it is closed and a new code is shown (whoever asked knew the old one). */
    fun deny(id: Long) = answer(id) { it.deny(id) }

    private fun answer(id: Long, give: (StreamServer) -> Unit) {
        val r = running ?: return
        if (r.server.clients().none { it.id == id && it.awaitingConfirmation }) return showNow()
        control.execute {
            give(r.server)
            scope.launch { if (running === r) showNow() }
        }
    }

    /**
     * While on: also pushes every message over UDP to [target] (`host:port`, a name or an address on the local
     * network), replacing an earlier push. Resolved and opened on [lookup]; meanwhile [UdpView.Starting].
     */
    fun pushUdp(target: String) {
        val r = running ?: return
        stopUdp()
        val request = ++udpRequest
        val text = target.trim()
        val hostPort = parseHostPort(text)
        if (hostPort == null) {
            udpView = UdpView.Failed(text, null)
            showNow()
            return
        }
        udpView = UdpView.Starting(text)
        showNow()
        lookup.execute {
            val result: Any = try {
                // The name is looked up here, off the main thread.
                val address = InetSocketAddress(hostPort.first, hostPort.second)
                when {
                    address.isUnresolved -> StreamFailure.HOST_UNKNOWN
                    !StreamServer.isLocalNetwork(address.address) -> StreamFailure.NOT_LOCAL
                    else -> UdpPush(address, offerNow).also { it.start() }
                }
            } catch (e: Exception) {
                log("cannot push to $text", e)
                StreamFailure.of(e)
            }
            scope.launch {
                val push = result as? UdpPush
                if (running !== r || request != udpRequest) {
                    push?.let { control.execute { it.stop() } }
                    return@launch
                }
                if (push != null) {
                    udp = push
                    udpView = null
                } else {
                    udpView = UdpView.Failed(text, (result as StreamFailure).text)
                }
                showNow()
            }
        }
    }

    /** Stops the UDP push (closed on [control]). */
    fun stopUdp() {
        udpRequest++
        val u = udp
        udp = null
        udpView = null
        if (u != null) control.execute { u.stop() }
        showNow()
    }

    /**
     * Stops streaming: the capture is let go at once, the server closed on [control]; then [StreamState.Off],
     * or [StreamState.Failed] with [failure] (the foreground service was refused).
     */
    fun stop(@StringRes failure: Int? = null) {
        if (running != null) stopUdp()
        controlledBy = null
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

        /** The UDP push's lookup: each task on a daemon thread of its own. */
        val LOOKUP: Executor = Executor { r -> Thread(r, "stream-udp-lookup").apply { isDaemon = true }.start() }
        const val STOP_TIMEOUT_MS = 500
        private val MAX_VALUES = SessionStream.entries.maxOf { it.valueCount }

        /** `host:port` (an IPv6 address in brackets) → the host and the port, or null. */
        internal fun parseHostPort(text: String): Pair<String, Int>? {
            val colon = text.lastIndexOf(':')
            if (colon <= 0) return null
            val host = text.substring(0, colon).removeSurrounding("[", "]")
            val port = text.substring(colon + 1).toIntOrNull()?.takeIf { it in 1..65535 } ?: return null
            return if (host.isBlank() || host.any { it.isWhitespace() }) null else host to port
        }

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
