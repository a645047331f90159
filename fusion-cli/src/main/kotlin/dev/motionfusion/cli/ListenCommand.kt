package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.stream.StreamCodec
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.ClockPinger
import dev.motionfusion.stream.StreamClient
import dev.motionfusion.core.session.SessionClock
import dev.motionfusion.stream.StreamEnd
import java.io.PrintStream
import java.net.URI
import java.nio.file.Files
import java.nio.file.Path
import java.time.Instant
import java.util.Locale
import java.util.concurrent.CountDownLatch
import java.util.concurrent.TimeUnit

/**
 * `fusion listen ws://HOST:PORT --code CODE`: receives a phone's live stream (docs/STREAMING.md) and
 * prints the orientation, writes a session folder (`-o DIR`, the app's format: `fusion replay` reads
 * it) or writes the orientation as CSV to standard output (`--csv`). [wallClockMs] is the laptop's
 * clock in ms since the epoch (latency through the phone's clock anchor).
 */
internal class ListenCommand(
    private val err: PrintStream,
    private val wallClockMs: () -> Double = { Instant.now().let { it.epochSecond * 1e3 + it.nano / 1e6 } },
    private val nanoTime: () -> Long = System::nanoTime,
) : Command {
    override val name = "listen"
    override val summary = "receive a phone's live stream: print the orientation, write a session (-o DIR) or CSV"
    override val help = """
        |Usage: fusion listen ws://HOST:PORT --code CODE [-o DIR | --csv] [--streams NAME,...] [--rate HZ] [--duration S]
        |       fusion listen ws://HOST:PORT ws://HOST:PORT... --code CODE[,CODE...] -o DIR [...]
        |
        |Several phones: one session folder each in DIR, named after the address (HOST-PORT), each with its clock exchanges
        |against this computer's clock (fusion align puts them on one timeline); --code gives one code for all or one per
        |address. Every 5 s a table of the phones (state, messages/s, dropped, clock uncertainty) goes to standard error. A
        |phone that leaves is connected to again every second, into a linked session beside the first (HOST-PORT.2, ...);
        |one that refuses or denies this laptop is given up (exit code 3 or 5 at the end). Ends at --duration or Ctrl-C.
        |
        |Connects to the app's stream (Stream switch on the phone; over USB: adb forward tcp:PORT tcp:PORT and
        |ws://127.0.0.1:PORT) with the pairing code the phone shows, and until the phone stops streaming, --duration S
        |seconds of sample time have passed, or Ctrl-C:
        |  (default)   prints the orientation ten times per second of sample time: azimuth, pitch, roll in degrees
        |  -o DIR      writes a session folder in the recording format (docs/SESSION_FORMAT.md), so that
        |              'fusion replay DIR' reads it; DIR must not exist or be empty
        |  --csv       writes every orientation to standard output: t_s,qw,qx,qy,qz,azimuth_deg,pitch_deg,roll_deg
        |              (sensor -> ENU; t_s the sensor timestamp in s)
        |--streams     the streams to receive (default all the phone offers): accelerometer, gyroscope, magnetometer,
        |              gyroscope_uncalibrated, magnetometer_uncalibrated, accelerometer_uncalibrated, rotation_vector,
        |              game_rotation_vector, orientation, filter_diagnostics
        |--rate HZ     at most HZ messages per stream per second
        |At the end a summary goes to standard error (on Ctrl-C too): messages per stream, the rate, what the phone dropped
        |because this client did not keep up, malformed messages skipped, the latency (the phone's sensor clock put on the
        |wall clock through its clock anchor, against this computer's clock: it includes the difference between the two
        |clocks), and how it ended. -o DIR is handed to the system at least once a second: a kill leaves a session that
        |'fusion recover DIR' repairs. The phone asks its user to allow a laptop it has not seen since streaming was
        |turned on ("fusion listen on HOST" and this computer's address): meanwhile "waiting for confirmation on the
        |phone..." is printed, for up to 60 s. Exit codes: 0 the phone stopped streaming or --duration passed; 1 a message
        |from the phone over 1 MiB; 3 no connection or pairing refused; 4 the connection was lost (no close from the phone,
        |or no answer to pings for 10-20 s); 5 denied on the phone, or not allowed there within 60 s; 130 Ctrl-C.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("--code", "-o", "--streams", "--rate", "--duration"), setOf("--csv"))
        if (o.positional.isEmpty()) throw UsageException("listen needs the phone's address, ws://HOST:PORT")
        val uris = o.positional.map(::phoneUri)
        if (uris.toSet().size < uris.size) throw UsageException("an address is given twice")
        val codes = phoneCodes(o.value("--code") ?: throw UsageException("listen needs --code, the pairing code the phone shows"), uris.size)
        val dir = o.value("-o")?.let { InputOptions.path(it) }
        if (dir != null && o.has("--csv")) throw UsageException("-o and --csv exclude each other")
        if (uris.size > 1 && dir == null) throw UsageException("listen with several phones needs -o DIR (one session folder each)")
        if (dir != null && Files.exists(dir) && (!Files.isDirectory(dir) || Files.list(dir).use { it.findAny().isPresent })) {
            throw UsageException("'${o.value("-o")}' exists and is not an empty folder")
        }
        val streams = o.value("--streams")?.split(',')?.map { name ->
            SessionStream.ofKey(name.trim())?.takeIf { it in StreamCodec.STREAMABLE } ?: throw UsageException("--streams: unknown stream '$name'")
        }
        val rate = o.double("--rate")?.also { if (it <= 0.0) throw UsageException("--rate must be positive") }
        val durationNs = o.double("--duration")?.let { if (it <= 0.0) throw UsageException("--duration must be positive"); (it * 1e9).toLong() }
        if (uris.size > 1) return ListenPhones(this, err, nanoTime, uris, codes, dir!!, streams, rate, durationNs).run()
        val uri = uris[0]
        val code = codes[0]

        val receiver = Receiver(out, dir, o.has("--csv"), durationNs, uri.toString())
        // The hello is taken on the connection's thread before the first sample: nothing comes before the header or the session.
        val pair = StreamMessage.Pair(code, streams, rate, client = CLIENT_NAME)
        val client = StreamClient(uri, pair, receiver::begin, receiver::malformed, receiver::take)
        try {
            client.connect(onWaiting = { err.println("fusion: waiting for confirmation on the phone... (allow this laptop there)") })
        } catch (e: java.io.IOException) {
            if (client.end == StreamEnd.DENIED) {
                err.println("fusion: ${e.message}")
                return ExitCode.DENIED
            }
            // Over the size limit before the hello was read (the hello and the large frame in one read): malformed input.
            if (client.end == StreamEnd.TOO_LARGE) {
                err.println("fusion: ${e.message}")
                return ExitCode.DATA_ERROR
            }
            throw e
        }
        // Ctrl-C (or a kill that lets Java end): the session closed and the summary printed all the same.
        val hook = Thread {
            if (receiver.finish("interrupted")) err.print(receiver.summary("ended: interrupted (Ctrl-C: exit code 130; another signal: 128 + its number)"))
        }
        Runtime.getRuntime().addShutdownHook(hook)
        var lastFlush = nanoTime()
        try {
            while (!receiver.done.await(FLUSH_POLL_MS, TimeUnit.MILLISECONDS)) {
                if (client.awaitClose(0)) break
                // Clock exchanges four times a second, where the phone answers them (docs/SYNC.md).
                receiver.ping()?.let { client.send(it) }
                // What was received is handed to the system at least once a second (as the app's recorder does).
                if (nanoTime() - lastFlush >= FLUSH_INTERVAL_NS) {
                    receiver.flush()
                    lastFlush = nanoTime()
                }
            }
        } finally {
            client.close()
        }
        val (reason, exit) = when {
            receiver.done.count == 0L -> "duration reached" to ExitCode.OK
            else -> when (client.end) {
                StreamEnd.PHONE_STOPPED, StreamEnd.CLOSED, null -> "the phone stopped streaming" to ExitCode.OK
                StreamEnd.TOO_LARGE -> (client.endReason ?: "a message too large") to ExitCode.DATA_ERROR
                StreamEnd.LOST -> (client.endReason ?: "connection lost") to ExitCode.CONNECTION_LOST
                StreamEnd.REFUSED, StreamEnd.DENIED -> (client.endReason ?: "closed by the phone") to ExitCode.CONNECTION_LOST
            }
        }
        val mine = receiver.finish(reason)
        runCatching { Runtime.getRuntime().removeShutdownHook(hook) }
        if (mine) err.print(receiver.summary("ended: $reason; exit code $exit"))
        return exit
    }

    /** Everything after the hello, on the connection's reading thread. */
    internal inner class Receiver(
        private val out: PrintStream,
        private val dir: Path?,
        private val csv: Boolean,
        private val durationNs: Long?,
        private val source: String,
        /** The first sample time of the phone, kept over its reconnections (--duration counts from it). */
        private val origin: LongArray = longArrayOf(Long.MIN_VALUE),
        /** What meta.json's source says after "fusion listen ADDRESS". */
        private val sourceNote: String = "",
    ) {
        val done = CountDownLatch(1)
        private var writer: SessionWriter? = null
        private var hello: StreamMessage.Hello? = null
        private val counts = LongArray(SessionStream.entries.size)
        private val firstTs = LongArray(SessionStream.entries.size)
        private val lastTs = LongArray(SessionStream.entries.size)
        private var malformed = 0L
        private var firstMalformed: String? = null
        private var firstT = Long.MIN_VALUE
        private var lastT = Long.MIN_VALUE
        private var lastPrintT = Long.MIN_VALUE
        private var dropped = 0L
        private val latencies = DoubleArray(MAX_LATENCIES)
        private var latencyCount = 0
        private var finished = false
        private val angles = DoubleArray(6)
        private val q = DoubleArray(4)
        private val link = laptopClock()
        private val pinger = ClockPinger(System::nanoTime, ::exchanged, link)

        @Synchronized
        fun begin(h: StreamMessage.Hello) {
            hello = h
            if (dir != null) {
                writer = SessionWriter.create(
                    dir, h.metadata.copy(source = "fusion listen $source$sourceNote", complete = false, streams = emptyMap(), clockLink = if (h.clock) link else null),
                )
            }
            if (csv) out.println("t_s,qw,qx,qy,qz,azimuth_deg,pitch_deg,roll_deg")
        }

        /** The next clock ping, when the phone answers them and the session is open. */
        @Synchronized
        fun ping(): StreamMessage.Ping? = if (hello?.clock == true && !finished) pinger.ping() else null

        /** A whole exchange: into clock.csv (the answer's arrival was stamped as it was read). */
        @Synchronized
        private fun exchanged(e: dev.motionfusion.core.sync.ClockExchange) {
            if (!finished) writer?.clockExchange(e, link)
        }

        fun take(m: StreamMessage) {
            // The answer's arrival is stamped before any lock is waited for.
            if (m is StreamMessage.Pong) {
                pinger.pong(m)
                return
            }
            takeLocked(m)
        }

        @Synchronized
        private fun takeLocked(m: StreamMessage) {
            if (finished) return
            val t = when (m) {
                is StreamMessage.Sample -> m.timestampNs
                is StreamMessage.Orientation -> m.timestampNs
                is StreamMessage.Status -> { dropped = m.dropped; return }
                else -> return
            }
            if (firstT == Long.MIN_VALUE) firstT = t
            if (origin[0] == Long.MIN_VALUE) origin[0] = t
            if (durationNs != null && t - origin[0] >= durationNs) {
                done.countDown()
                return
            }
            lastT = maxOf(lastT, t)
            val i = if (m is StreamMessage.Sample) m.stream.ordinal else SessionStream.ORIENTATION.ordinal
            if (counts[i] == 0L) firstTs[i] = t
            lastTs[i] = t
            when (m) {
                is StreamMessage.Sample -> {
                    counts[m.stream.ordinal]++
                    writer?.write(m.stream, m.timestampNs, m.values, 0, m.values.size, if (m.stream.hasAccuracy) m.accuracy else -1)
                }
                is StreamMessage.Orientation -> {
                    counts[SessionStream.ORIENTATION.ordinal]++
                    hello?.metadata?.startAnchor?.let { a ->
                        if (latencyCount < MAX_LATENCIES) latencies[latencyCount++] = wallClockMs() - a.toWallClockMs(t)
                    }
                    writer?.orientation(t, m.qw, m.qx, m.qy, m.qz)
                    if (writer == null) show(m)
                }
                else -> Unit
            }
        }

        private fun show(m: StreamMessage.Orientation) {
            q[0] = m.qw; q[1] = m.qx; q[2] = m.qy; q[3] = m.qz
            dev.motionfusion.core.Orientations.androidAndAerospaceAngles(q, angles, 0)
            val az = Math.toDegrees(angles[0]); val pitch = Math.toDegrees(angles[1]); val roll = Math.toDegrees(angles[2])
            if (csv) {
                out.println("${m.timestampNs / 1e9},${m.qw},${m.qx},${m.qy},${m.qz},$az,$pitch,$roll")
            } else if (lastPrintT == Long.MIN_VALUE || m.timestampNs - lastPrintT >= 100_000_000L) {
                lastPrintT = m.timestampNs
                out.println(String.format(Locale.ROOT, "t %10.3f s  azimuth %7.2f°  pitch %7.2f°  roll %7.2f°", m.timestampNs / 1e9, az, pitch, roll))
            }
        }

        /** A message that could not be read: skipped and counted; the first is named at once and in the summary. */
        @Synchronized
        fun malformed(reason: String) {
            if (malformed++ == 0L) {
                firstMalformed = reason
                err.println("skipped a malformed message (later ones are counted): $reason")
            }
        }

        /** Messages taken so far (samples and orientations). */
        @Synchronized
        fun received(): Long = counts.sum()

        /** What the phone dropped for this client so far (its last status). */
        @Synchronized
        fun droppedByPhone(): Long = dropped

        /** The live clock estimate, null before two exchanges (or when the phone does not answer pings). */
        fun clock(): dev.motionfusion.core.sync.ClockMapping? = pinger.mapping()

        /** The session folder, once the hello came with -o. */
        @Synchronized
        fun directory(): Path? = writer?.directory

        /** Hands what was received to the system (survives a killed process). */
        @Synchronized
        fun flush() {
            if (!finished) writer?.flush()
            out.flush()
        }

        /** Closes the session with [reason]; false when it was already closed (by the other of Ctrl-C and the end). */
        @Synchronized
        fun finish(reason: String): Boolean {
            if (finished) return false
            finished = true
            writer?.close(if (lastT == Long.MIN_VALUE) null else lastT, reason)
            out.flush()
            return true
        }

        @Synchronized
        fun summary(end: String): String = buildString {
            val seconds = if (firstT == Long.MIN_VALUE) 0.0 else (lastT - firstT) / 1e9
            appendLine(String.format(Locale.ROOT, "%.1f s of sample time from %s", seconds, source))
            for (s in SessionStream.entries) {
                val n = counts[s.ordinal]
                // n messages span n - 1 intervals.
                val span = (lastTs[s.ordinal] - firstTs[s.ordinal]) / 1e9
                if (n > 0) appendLine(String.format(Locale.ROOT, "  %-28s %9d messages  %8.1f Hz", s.key, n, if (n > 1 && span > 0) (n - 1) / span else 0.0))
            }
            appendLine("  dropped by the phone (this client did not keep up): $dropped")
            if (malformed > 0) appendLine("  malformed messages skipped: $malformed (the first: $firstMalformed)")
            if (latencyCount > 0) {
                val sorted = latencies.copyOf(latencyCount).also { it.sort() }
                appendLine(
                    String.format(
                        Locale.ROOT, "  latency of the orientation: median %.1f ms, p99 %.1f ms (phone clock anchor against this clock)",
                        sorted[latencyCount / 2], sorted[minOf(latencyCount - 1, (latencyCount * 0.99).toInt())],
                    ),
                )
            }
            val clock = pinger.mapping()
            when {
                hello?.clock != true -> appendLine("  clock: this phone does not answer clock pings (an older app): fusion align can use its wall clock")
                clock == null -> appendLine("  clock: fewer than two exchanges with the phone")
                else -> appendLine(
                    String.format(
                        Locale.ROOT, "  clock: the phone's sensor clock is %.6f s ahead of this one, drifting %+.1f ppm, ±%.2f ms (%d exchanges, %d unanswered)",
                        clock.offsetNs / 1e9, clock.driftPpm, clock.uncertaintyNs / 1e6, pinger.exchanges, pinger.unanswered,
                    ),
                )
            }
            writer?.let { appendLine("  session written to ${it.directory}") }
            appendLine(end)
        }
    }

    internal companion object {
        const val MAX_LATENCIES = 1_000_000

        /** The name this laptop gives the phone, shown when the phone asks its user. */
        val CLIENT_NAME: String by lazy { "fusion listen on ${hostName()}" }

        /** [url] as a phone's address, ws://HOST:PORT. */
        fun phoneUri(url: String): URI = runCatching { URI(url) }.getOrNull()?.takeIf { it.scheme == "ws" && it.host != null && it.port in 1..65535 }
            ?: throw UsageException("'$url' is not an address ws://HOST:PORT")

        /** --code: one code for every phone, or one per address, comma-separated in the same order. */
        fun phoneCodes(value: String, phones: Int): List<String> {
            val codes = value.split(',').map { it.trim() }
            if (codes.any { it.isEmpty() }) throw UsageException("--code: an empty code in '$value'")
            return when (codes.size) {
                1 -> List(phones) { codes[0] }
                phones -> codes
                else -> throw UsageException("--code: ${codes.size} codes for $phones phones (give one for all, or one per address in their order)")
            }
        }
        /** The main loop's period: also the clock pings' (4 a second). */
        const val FLUSH_POLL_MS = 250L
        const val FLUSH_INTERVAL_NS = 500_000_000L

        /**
         * This computer's monotonic clock (System.nanoTime), named so that sessions on the same clock can be told: the
         * host and, on Linux, its boot (the clock restarts with it); elsewhere this process only.
         */
        fun laptopClock(): String {
            val boot = runCatching { Files.readString(java.nio.file.Paths.get("/proc/sys/kernel/random/boot_id")).trim() }.getOrNull()?.takeIf { it.isNotEmpty() }
            return "${hostName()} " + (boot?.let { "boot $it" } ?: "process ${ProcessHandle.current().pid()} started ${java.lang.management.ManagementFactory.getRuntimeMXBean().startTime}")
        }

        /** This computer's name, for the phone's question to its user. */
        fun hostName(): String = listOf("HOSTNAME", "COMPUTERNAME").firstNotNullOfOrNull { System.getenv(it)?.takeIf(String::isNotBlank) }
            ?: runCatching { java.net.InetAddress.getLocalHost().hostName }.getOrNull() ?: "this computer"
    }
}
