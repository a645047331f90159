package dev.motionfusion.cli

import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.stream.ClockPinger
import dev.motionfusion.stream.StreamClient
import dev.motionfusion.stream.StreamEnd
import dev.motionfusion.stream.StreamServer
import java.io.IOException
import java.io.PrintStream
import java.net.URI
import java.util.Locale
import java.util.concurrent.CountDownLatch
import java.util.concurrent.LinkedBlockingQueue
import java.util.concurrent.TimeUnit
import java.util.concurrent.locks.LockSupport

/**
 * `fusion record start|stop|mark URL… --code CODE`: starts or stops a recording on one or many phones at once, or marks a
 * moment in it (docs/STREAMING.md, "Remote control"). Each phone is paired, its clock put on this laptop's by
 * [PINGS] clock exchanges, and then all are given the same instant on this laptop's clock ([nanoTime]), each on its own
 * sensor clock: a start `--delay` ahead, so that the command reaches every phone before it and the recordings begin
 * together; a stop or mark now.
 */
internal class RecordCommand(
    private val err: PrintStream,
    private val nanoTime: () -> Long = System::nanoTime,
) : Command {
    override val name = "record"
    override val summary = "start or stop a recording on one or several phones, or mark a moment (remote control)"
    override val help = """
        |Usage: fusion record start|stop|mark ws://HOST:PORT... --code CODE[,CODE...] [--label TEXT] [--delay S]
        |
        |Remote control of the app over its live stream (Stream screen: streaming on and "Allow remote control" on):
        |  start   starts a recording on every phone, as if Record were pressed there, tagged with this laptop's clock
        |          (meta.json's remote_start); all begin at the same instant of this laptop's clock, --delay S ahead
        |          (default 0.5): no phone keeps a sample before it
        |  stop    stops the recordings
        |  mark    adds a marker (--label TEXT its note) at this instant, on each phone's clock
        |--code    the pairing code each phone shows: one for all, or one per address in their order
        |Each phone's answer is printed, one line each. The phone asks its user to allow a laptop it has not seen since
        |streaming was turned on. Exit codes: 0 every phone did it; 1 a phone could not (e.g. already recording, not
        |recording); 3 no connection or pairing refused; 5 denied on a phone, or remote control is off there.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("--code", "--label", "--delay"), emptySet())
        val word = o.positional.firstOrNull() ?: throw UsageException("record needs start, stop or mark")
        val command = StreamMessage.Control.Command.entries.firstOrNull { it.key == word }
            ?: throw UsageException("record: unknown action '$word' (start, stop or mark)")
        val uris = o.positional.drop(1).map(ListenCommand::phoneUri)
        if (uris.isEmpty()) throw UsageException("record $word needs the phones' addresses, ws://HOST:PORT")
        if (uris.toSet().size < uris.size) throw UsageException("an address is given twice")
        val codes = ListenCommand.phoneCodes(o.value("--code") ?: throw UsageException("record needs --code, the pairing code the phone shows"), uris.size)
        val label = o.value("--label")
        if (label != null && command != StreamMessage.Control.Command.MARK) throw UsageException("--label is for mark")
        val delayNs = ((o.double("--delay") ?: 0.5).also { if (it < 0 || it > 60) throw UsageException("--delay must be 0 to 60 s") } * 1e9).toLong()

        val phones = uris.indices.map { Phone(uris[it], codes[it]) }
        val ready = CountDownLatch(phones.size)
        val go = CountDownLatch(1)
        val instant = java.util.concurrent.atomic.AtomicLong()
        val threads = phones.map { p ->
            Thread({ p.run(ready, go, instant::get, command, label) }, "record-${p.uri.port}").apply { isDaemon = true; start() }
        }
        ready.await(CONNECT_LIMIT_MS, TimeUnit.MILLISECONDS)
        // One instant of this laptop's clock for all, taken once every phone is paired and its clock known.
        instant.set(nanoTime() + if (command == StreamMessage.Control.Command.START) delayNs else 0L)
        go.countDown()
        threads.forEach { it.join(CONNECT_LIMIT_MS + ANSWER_LIMIT_MS) }
        var exit = ExitCode.OK
        for (p in phones) {
            out.println("${p.uri}: ${p.outcome ?: "no answer"}")
            exit = maxOf(exit, p.exit)
        }
        return exit
    }

    private inner class Phone(val uri: URI, val code: String) {
        @Volatile var outcome: String? = null

        @Volatile var exit = ExitCode.IO_ERROR
        private val pongs = LinkedBlockingQueue<StreamMessage.Pong>()
        private val results = LinkedBlockingQueue<StreamMessage.ControlResult>()
        private val pinger = ClockPinger(nanoTime)

        fun run(ready: CountDownLatch, go: CountDownLatch, instant: () -> Long, command: StreamMessage.Control.Command, label: String?) {
            val client = StreamClient(
                uri, StreamMessage.Pair(code, emptyList(), client = CLIENT_NAME),
                onMessage = { m ->
                    when (m) {
                        is StreamMessage.Pong -> pinger.pong(m)?.let { pongs += m }
                        is StreamMessage.ControlResult -> results += m
                        else -> Unit
                    }
                },
            )
            try {
                val hello = try {
                    client.connect(onWaiting = { err.println("fusion: $uri: waiting for confirmation on the phone... (allow this laptop there)") })
                } catch (e: IOException) {
                    exit = if (client.end == StreamEnd.DENIED) ExitCode.DENIED else ExitCode.IO_ERROR
                    outcome = e.message?.removePrefix("$uri: ") ?: "no connection"
                    return
                } finally {
                    ready.countDown()
                }
                if (hello.clock) exchange(client)
                go.await()
                val laptopNs = instant()
                val mapping = pinger.mapping()
                val control = StreamMessage.Control(1, command, laptopNs, mapping?.toPhone(laptopNs), ListenCommand.laptopClock(), label)
                if (!client.send(control)) {
                    outcome = "connection lost: ${client.endReason ?: "closed"}"
                    return
                }
                val answer = results.poll(ANSWER_LIMIT_MS, TimeUnit.MILLISECONDS)
                val clock = mapping?.let { String.format(Locale.ROOT, " (clock ±%.2f ms, %d exchanges)", it.uncertaintyNs / 1e6, it.exchanges) }
                    ?: " (no clock exchanges: the phone's time of receipt)"
                when {
                    answer == null && client.awaitClose(REFUSAL_CLOSE_MS) && client.end != StreamEnd.CLOSED ->
                        outcome = "refused: ${client.endReason ?: "closed"}"
                    answer == null -> outcome = "no answer within ${ANSWER_LIMIT_MS / 1000} s"
                    !answer.ok -> {
                        outcome = "refused: ${answer.reason}"
                        exit = if (answer.reason == StreamServer.REMOTE_CONTROL_OFF) ExitCode.DENIED else ExitCode.DATA_ERROR
                    }
                    else -> {
                        val done = when (command) {
                            StreamMessage.Control.Command.START -> "started"
                            StreamMessage.Control.Command.STOP -> "stopped"
                            StreamMessage.Control.Command.MARK -> "marked"
                        }
                        outcome = "$done${answer.session?.let { " ($it)" } ?: ""}$clock"
                        exit = ExitCode.OK
                    }
                }
                // A refusal of remote control closes the connection (4013): the phone's reason says why.
                if (answer?.ok == false && answer.reason == StreamServer.REMOTE_CONTROL_OFF) exit = ExitCode.DENIED
            } finally {
                runCatching { client.close() }
            }
        }

        /** [PINGS] clock exchanges, one at a time, at least [PING_SPACING_NS] apart (the phone answers one per 10 ms). */
        private fun exchange(client: StreamClient) {
            var last = Long.MIN_VALUE
            for (k in 0 until PINGS) {
                if (last != Long.MIN_VALUE) {
                    val wait = last + PING_SPACING_NS - nanoTime()
                    if (wait > 0) LockSupport.parkNanos(wait)
                }
                last = nanoTime()
                if (!client.send(pinger.ping())) return
                pongs.poll(PONG_LIMIT_MS, TimeUnit.MILLISECONDS)
            }
        }
    }

    private companion object {
        /** Clock exchanges before the command: half a second at the pace below. */
        const val PINGS = 25
        const val PING_SPACING_NS = 20_000_000L
        const val PONG_LIMIT_MS = 1_000L
        const val CONNECT_LIMIT_MS = 130_000L
        const val ANSWER_LIMIT_MS = 5_000L
        const val REFUSAL_CLOSE_MS = 2_000L
        val CLIENT_NAME: String by lazy { "fusion record on ${ListenCommand.hostName()}" }
    }
}
