/*
 * The sampling rate of one stream's timestamps, gaps left out: the one rule for a rate that the
 * exports' metadata, the Allan deviation and `fusion summary` state.
 */
package dev.motionfusion.core.event

/**
 * Feeds timestamps (ns, in arrival order) with [add]; [hz] is the number of intervals over their
 * sum. An interval that does not advance is a stall and not counted; one over five times the mean
 * interval so far, once ten are known, is a gap, over which nothing was sampled, and not counted
 * either: a recording paused for a minute still gives its sensor's rate. Constant memory.
 */
public class SampleRate {
    /** What the interval before a timestamp was. */
    public enum class Interval {
        /** The first timestamp: no interval before it. */
        FIRST,

        /** An interval of the stream's sampling. */
        SAMPLE,

        /** The timestamp did not advance (equal or earlier). */
        STALL,

        /** Over five times the mean interval so far: a gap. */
        GAP,
    }

    private var last = 0L
    private var started = false

    /** Intervals counted and their sum, ns. */
    public var intervals: Long = 0L
        private set
    public var intervalSumNs: Long = 0L
        private set

    /** Gaps seen, and the longest, ns. */
    public var gaps: Long = 0L
        private set
    public var longestGapNs: Long = 0L
        private set

    /** Adds [timestampNs]; says what the interval before it was. */
    public fun add(timestampNs: Long): Interval {
        if (!started) {
            started = true
            last = timestampNs
            return Interval.FIRST
        }
        val dt = timestampNs - last
        last = timestampNs
        return when {
            dt <= 0L -> Interval.STALL
            intervals > MIN_INTERVALS && dt.toDouble() > GAP_FACTOR * intervalSumNs / intervals -> {
                gaps++
                if (dt > longestGapNs) longestGapNs = dt
                Interval.GAP
            }
            else -> {
                intervalSumNs += dt
                intervals++
                Interval.SAMPLE
            }
        }
    }

    /** The rate, Hz; NaN before an interval is counted. */
    public val hz: Double get() = if (intervals == 0L) Double.NaN else intervals * 1e9 / intervalSumNs

    private companion object {
        const val MIN_INTERVALS = 10L
        const val GAP_FACTOR = 5.0
    }
}
