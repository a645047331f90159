package dev.motionfusion.cli

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.StreamClient
import dev.motionfusion.stream.StreamEnd
import java.io.IOException
import java.io.PrintStream
import java.net.URI
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale
import java.util.concurrent.TimeUnit

/**
 * `fusion listen URL URL… -o DIR`: several phones at once (docs/SYNC.md, "Several phones"). Each phone gets its own
 * session folder in DIR, named after its address (`127.0.0.1-8765`), with its clock exchanges against this laptop's
 * clock, so that `fusion align` of the folders puts them on one timeline. A phone that leaves (connection lost, streaming turned
 * off) is connected to again every second; when it is back, its samples go into a new session folder beside the first,
 * the same name with `.2`, `.3`… (a linked session: the same laptop clock in `clock_link`, its own clock exchanges, the
 * phone's hello of the new connection in its meta.json). A phone that refuses the pairing or whose user denies it is
 * given up. Every [STATUS_INTERVAL_NS] a table of the phones (state, rate, drops, clock uncertainty) goes to [err].
 *
 * Ends when every phone has reached `--duration` (of its own sample time, over its reconnections) or was given up, or on
 * Ctrl-C. Exit code: 0, else that of the worst phone given up (5 denied, 3 refused).
 */
internal class ListenPhones(
    private val command: ListenCommand,
    private val err: PrintStream,
    private val nanoTime: () -> Long,
    uris: List<URI>,
    codes: List<String>,
    private val dir: Path,
    private val streams: List<SessionStream>?,
    private val rate: Double?,
    private val durationNs: Long?,
) {
    private val phones = uris.indices.map { Phone(uris[it], codes[it]) }

    private inner class Phone(val uri: URI, val code: String) {
        val name = "${uri.host.removePrefix("[").removeSuffix("]").replace(':', '_')}-${uri.port}"
        val origin = longArrayOf(Long.MIN_VALUE)

        /** Sessions begun (connections that got as far as the hello). */
        @Volatile var parts = 0

        @Volatile var receiver: ListenCommand.Receiver? = null

        @Volatile var client: StreamClient? = null

        @Volatile var state = "connecting"

        /** Why the phone was given up, and the exit code it stands for; null while it is listened to. */
        @Volatile var gaveUp: Pair<String, Int>? = null

        @Volatile var finished = false
        val summaries = ArrayList<String>()
        var receivedAtStatus = 0L
        var statusNs = 0L
        val thread = Thread(::run, "listen-$name").apply { isDaemon = true }

        private fun run() {
            var announcedWait = false
            while (!stopping) {
                val folder = dir.resolve(if (parts == 0) name else "$name.${parts + 1}")
                val r = command.Receiver(NULL_OUT, folder, false, durationNs, uri.toString(), origin, if (parts == 0) "" else " (connection ${parts + 1})")
                val c = StreamClient(uri, StreamMessage.Pair(code, streams, rate, client = ListenCommand.CLIENT_NAME), r::begin, r::malformed, r::take)
                try {
                    c.connect(onWaiting = {
                        state = "waiting for its user"
                        err.println("fusion: $uri: waiting for confirmation on the phone... (allow this laptop there)")
                    })
                } catch (e: IOException) {
                    when (c.end) {
                        StreamEnd.DENIED -> return giveUp(e.message ?: "denied", ExitCode.DENIED)
                        StreamEnd.REFUSED -> return giveUp(e.message ?: "refused", ExitCode.IO_ERROR)
                        StreamEnd.TOO_LARGE -> return giveUp(e.message ?: "too large", ExitCode.DATA_ERROR)
                        else -> {
                            // Not there (yet, or again): tried again every second.
                            if (!announcedWait) err.println("fusion: $uri: ${e.message}; trying again every second")
                            announcedWait = true
                            state = if (parts == 0) "connecting" else "away"
                            if (stopLatch.await(RETRY_MS, TimeUnit.MILLISECONDS)) return
                            continue
                        }
                    }
                }
                announcedWait = false
                receiver = r
                parts++
                client = c
                state = "receiving"
                err.println("fusion: $uri: receiving into ${r.directory() ?: folder}")
                while (!stopping && !r.done.await(POLL_MS, TimeUnit.MILLISECONDS)) {
                    if (c.awaitClose(0)) break
                }
                runCatching { c.close() }
                val reason = when {
                    r.done.count == 0L -> "duration reached"
                    stopping -> "interrupted"
                    c.end == StreamEnd.LOST -> c.endReason ?: "connection lost"
                    else -> "the phone stopped streaming"
                }
                end(r, reason)
                if (r.done.count == 0L) {
                    state = "done"
                    finished = true
                    return
                }
                if (stopping) return
                state = "away"
                err.println("fusion: $uri: $reason; trying to connect again every second (a new session beside the last)")
                if (stopLatch.await(RETRY_MS, TimeUnit.MILLISECONDS)) return
            }
        }

        fun end(r: ListenCommand.Receiver, reason: String) {
            // The receiver stays for the table (its drops and clock); a finished one is neither pinged nor flushed.
            if (r.finish(reason)) synchronized(summaries) { summaries += r.summary("ended: $reason") }
        }

        private fun giveUp(reason: String, exit: Int) {
            gaveUp = reason to exit
            state = "given up"
            finished = true
            err.println("fusion: $reason (given up)")
        }

        /** One line of the status table. */
        fun line(now: Long): String {
            val r = receiver
            val total = r?.received() ?: 0L
            val rateHz = if (r == null || statusNs == 0L || total < receivedAtStatus || state != "receiving") null else (total - receivedAtStatus) * 1e9 / (now - statusNs)
            receivedAtStatus = total
            statusNs = now
            val clock = r?.clock()
            return String.format(
                Locale.ROOT, "  %-24s %-20s %10s %10s %12s  %s", name, state, rateHz?.let { String.format(Locale.ROOT, "%.1f", it) } ?: "-", r?.droppedByPhone()?.toString() ?: "-",
                clock?.let { String.format(Locale.ROOT, "±%.2f ms", it.uncertaintyNs / 1e6) } ?: "-", if (parts > 1) "session ${parts}" else "",
            )
        }
    }

    @Volatile private var stopping = false
    private val stopLatch = java.util.concurrent.CountDownLatch(1)

    fun run(): Int {
        if (Files.exists(dir) && (!Files.isDirectory(dir) || Files.list(dir).use { it.findAny().isPresent })) {
            throw UsageException("'$dir' exists and is not an empty folder")
        }
        Files.createDirectories(dir)
        val hook = Thread { stop(); printSummaries("interrupted (Ctrl-C: exit code 130)") }
        Runtime.getRuntime().addShutdownHook(hook)
        phones.forEach { it.thread.start() }
        var lastFlush = nanoTime()
        var lastStatus = nanoTime()
        while (phones.any { !it.finished }) {
            if (stopLatch.await(POLL_MS, TimeUnit.MILLISECONDS)) break
            for (p in phones) {
                val r = p.receiver ?: continue
                if (p.state != "receiving") continue
                // Clock exchanges four times a second with each phone that answers them.
                r.ping()?.let { p.client?.send(it) }
            }
            val now = nanoTime()
            if (now - lastFlush >= FLUSH_INTERVAL_NS) {
                phones.forEach { it.receiver?.flush() }
                lastFlush = now
            }
            if (now - lastStatus >= STATUS_INTERVAL_NS) {
                err.print(table(now))
                lastStatus = now
            }
        }
        phones.forEach { it.thread.join(10_000) }
        runCatching { Runtime.getRuntime().removeShutdownHook(hook) }
        val exit = phones.mapNotNull { it.gaveUp?.second }.maxOrNull() ?: ExitCode.OK
        err.print(table(nanoTime()))
        printSummaries("exit code $exit")
        return exit
    }

    private fun stop() {
        stopping = true
        stopLatch.countDown()
        for (p in phones) {
            p.receiver?.let { p.end(it, "interrupted") }
        }
    }

    private fun table(now: Long): String = buildString {
        appendLine(String.format(Locale.ROOT, "  %-24s %-20s %10s %10s %12s", "phone", "state", "msg/s", "dropped", "clock"))
        for (p in phones) appendLine(p.line(now))
    }

    @Synchronized
    private fun printSummaries(end: String) {
        for (p in phones) {
            synchronized(p.summaries) {
                for (s in p.summaries) err.print(s)
                p.summaries.clear()
            }
            p.gaveUp?.let { err.println("${p.uri}: given up: ${it.first}") }
        }
        err.println("${phones.size} phones, ${phones.sumOf { it.parts }} sessions in $dir; $end")
    }

    private companion object {
        const val POLL_MS = 250L
        const val RETRY_MS = 1_000L
        const val FLUSH_INTERVAL_NS = 500_000_000L
        const val STATUS_INTERVAL_NS = 5_000_000_000L
        val NULL_OUT = PrintStream(java.io.OutputStream.nullOutputStream())
    }
}
