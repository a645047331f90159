package dev.motionfusion.stream

import dev.motionfusion.core.stream.StreamMessage
import dev.motionfusion.core.sync.ClockExchange
import dev.motionfusion.core.sync.ClockMapping
import dev.motionfusion.core.sync.ClockSync

/**
 * The laptop's half of the clock exchanges over a link (docs/SYNC.md): [ping] makes the next
 * [StreamMessage.Ping] (stamped on [nanoTime], the laptop's monotonic clock, and carrying when the
 * previous answer arrived, so that the phone holds whole exchanges too); [pong] takes the phone's
 * answer, stamps its arrival at once, and gives the whole exchange to [onExchange] and to the live
 * estimate ([mapping]). An answer to anything but the last ping, or one that contradicts itself, is
 * not used ([unanswered] counts pings whose answer never came or came late). Call [pong] from the
 * connection's reading thread as the answer arrives; [ping] from any one thread.
 */
public class ClockPinger @JvmOverloads constructor(
    private val nanoTime: () -> Long = System::nanoTime,
    private val onExchange: (ClockExchange) -> Unit = {},
    /** This clock's name, carried by every ping (meta.json's `clock_link` of a session the phone records while linked). */
    private val laptopClock: String? = null,
) {
    private val lock = Any()
    private val sync = ClockSync()
    private var nextId = 1L
    private var pendingId = 0L
    private var pendingT1 = 0L
    private var lastId: Long? = null
    private var lastT4: Long? = null

    /** Pings sent whose answer was not used. */
    public var unanswered: Long = 0
        private set

    /** Whole exchanges made. */
    public var exchanges: Long = 0
        private set

    /** The next ping to send, stamped now. */
    public fun ping(): StreamMessage.Ping = synchronized(lock) {
        if (pendingId != 0L) unanswered++
        pendingId = nextId++
        pendingT1 = nanoTime()
        StreamMessage.Ping(pendingId, pendingT1, lastId, lastT4, laptopClock)
    }

    /** Takes the phone's answer; returns the exchange it completed, or null when it answers no pending ping. */
    public fun pong(p: StreamMessage.Pong): ClockExchange? {
        val t4 = nanoTime()
        val exchange = synchronized(lock) {
            if (p.id != pendingId || p.t1Ns != pendingT1) return null
            pendingId = 0
            val e = ClockExchange(p.t1Ns, p.t2Ns, p.t3Ns, t4)
            if (!sync.add(e)) return null
            lastId = p.id
            lastT4 = t4
            exchanges++
            e
        }
        onExchange(exchange)
        return exchange
    }

    /** The live estimate of the phone's clock on this one (the last 10 minutes of exchanges), null before two. */
    public fun mapping(): ClockMapping? = synchronized(lock) { sync.mapping() }
}
