/*
 * A simulated link between a laptop and a phone whose clocks differ: the phone's clock runs at
 * (1 + drift) times the laptop's from an offset, and each message takes a shortest delay plus a
 * random jitter each way. What the clock estimate (dev.motionfusion.core.sync) is tested and
 * measured against, with the truth known.
 */
package dev.motionfusion.core.sim

import dev.motionfusion.core.sync.ClockExchange
import java.util.SplittableRandom

/**
 * @property offsetNs the phone's clock minus the laptop's at laptop time 0, ns.
 * @property driftPpm how much faster the phone's clock runs, ppm.
 * @property upMinNs / [downMinNs] the shortest one-way delay laptop → phone and back, ns.
 * @property jitterNs each one-way delay adds a uniform random jitter in [0, jitterNs).
 * @property replyNs the phone's time between receiving and replying, up to this much (uniform).
 */
public class SimulatedClockLink(
    public val offsetNs: Long,
    public val driftPpm: Double,
    public val upMinNs: Long = 300_000,
    public val downMinNs: Long = 300_000,
    public val jitterNs: Long = 20_000_000,
    public val replyNs: Long = 1_000_000,
    seed: Long = 1,
) {
    init {
        require(driftPpm.isFinite() && Math.abs(driftPpm) < 10_000) { "driftPpm must be finite and below 1 %: $driftPpm" }
        require(upMinNs >= 0 && downMinNs >= 0 && jitterNs >= 0 && replyNs >= 0) { "delays must be ≥ 0" }
    }

    private val random = SplittableRandom(seed)

    /** The phone's clock at laptop time [laptopNs]. */
    public fun phoneAt(laptopNs: Long): Long = laptopNs + offsetNs + Math.round(laptopNs * driftPpm * 1e-6)

    /** The true offset (phone − laptop) at laptop time [laptopNs], ns. */
    public fun trueOffsetAt(laptopNs: Long): Long = phoneAt(laptopNs) - laptopNs

    /** One exchange whose request leaves the laptop at [laptopNs]. */
    public fun exchange(laptopNs: Long): ClockExchange {
        val up = upMinNs + jitter()
        val reply = if (replyNs == 0L) 0 else random.nextLong(replyNs + 1)
        val down = downMinNs + jitter()
        val arrive = laptopNs + up
        val leave = arrive + reply
        return ClockExchange(laptopNs, phoneAt(arrive), phoneAt(leave), leave + down)
    }

    private fun jitter(): Long = if (jitterNs == 0L) 0 else random.nextLong(jitterNs)
}
