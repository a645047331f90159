/*
 * One clock for several phones (docs/SYNC.md). Over a live link the laptop and a phone exchange
 * timestamped pings; from them this file estimates the phone's clock on the laptop's.
 *
 * An exchange has four times, all in ns: the laptop sends at t1 and receives the reply at t4 (the
 * laptop's monotonic clock); the phone receives at t2 and replies at t3 (its elapsedRealtimeNanos,
 * the clock of SensorEvent.timestamp). With the phone's clock = laptop's clock + offset, and
 * one-way delays d↑, d↓ ≥ 0:
 *
 *     t2 − t1 = offset + d↑   ≥ offset      (an upper bound of the offset at t1)
 *     t3 − t4 = offset − d↓   ≤ offset      (a lower bound of the offset at t4)
 *
 * Both clocks are taken as linear against each other over the window (offset + drift × time: a
 * phone's crystal drifts by tens of ppm, steadily over minutes). The offset line then lies below
 * every upper bound and above every lower bound. The estimate takes the highest line under the
 * upper bounds (an edge of their lower convex hull) and the lowest line over the lower bounds (an
 * edge of their upper hull), both chosen at the window's middle, and averages them: exact when the
 * shortest delay each way is the same, whatever the jitter of the others. Half the distance
 * between the two lines bounds the error for any asymmetry of the shortest delays: it is the
 * stated uncertainty. This is the idea of NTP's minimum-delay filter taken over a whole window.
 */
package dev.motionfusion.core.sync

/**
 * A phone's clock on a laptop's: laptop time = phone time − offset, where the offset changes
 * linearly with the phone's time ([driftPpm], parts per million of elapsed time).
 *
 * @property referencePhoneNs the phone time at which [offsetNs] holds.
 * @property offsetNs phone clock minus laptop clock at [referencePhoneNs], ns.
 * @property driftPpm change of the offset per unit of phone time, in ppm (1 ppm = 1 µs per second).
 * @property uncertaintyNs half-width of the interval that holds the true offset at
 *   [referencePhoneNs] whatever the split of the shortest round trip between its two ways, ns.
 * @property exchanges how many exchanges the estimate rests on.
 */
public data class ClockMapping(
    val referencePhoneNs: Long,
    val offsetNs: Double,
    val driftPpm: Double,
    val uncertaintyNs: Double,
    val exchanges: Int,
) {
    init {
        require(offsetNs.isFinite() && driftPpm.isFinite() && uncertaintyNs.isFinite() && uncertaintyNs >= 0) {
            "a clock mapping needs finite figures and an uncertainty ≥ 0: $this"
        }
        require(exchanges >= 0) { "exchanges must be ≥ 0: $exchanges" }
    }

    /** The offset (phone − laptop, ns) at phone time [phoneNs]. */
    public fun offsetAt(phoneNs: Long): Double = offsetNs + driftPpm * 1e-6 * (phoneNs - referencePhoneNs).toDouble()

    /** Phone time [phoneNs] (e.g. a SensorEvent.timestamp) on the laptop's clock, ns. */
    public fun toLaptop(phoneNs: Long): Long = phoneNs - Math.round(offsetAt(phoneNs))

    /** Laptop time [laptopNs] on the phone's clock, ns. */
    public fun toPhone(laptopNs: Long): Long {
        // offset(p) = o + k (p − r) and p = l + offset(p): p = (l + o − k r) / (1 − k).
        val k = driftPpm * 1e-6
        return Math.round((laptopNs.toDouble() + offsetNs - k * referencePhoneNs.toDouble()) / (1 - k))
    }
}

/** One ping exchange, ns: [t1] laptop sent, [t2] phone received, [t3] phone replied, [t4] laptop received. */
public data class ClockExchange(val t1: Long, val t2: Long, val t3: Long, val t4: Long) {
    /** The round trip without the phone's own time, ns (≥ 0 for a real exchange). */
    public val delayNs: Long get() = (t4 - t1) - (t3 - t2)

    /** NTP's offset of this exchange alone (phone − laptop), ns. */
    public val offsetNs: Double get() = ((t2 - t1).toDouble() + (t3 - t4).toDouble()) / 2
}

/**
 * Estimates a [ClockMapping] from the last [window] exchanges (older ones are forgotten, so a
 * drift that changes over hours is followed), as a live link needs it.
 * Exchanges arrive in the laptop's order; one whose times contradict themselves (a reply before
 * its request on either clock, or a laptop time that goes back) is refused and counted in
 * [refused]. Not thread-safe. A recording that keeps its exchanges is put on the laptop's clock
 * afterwards by [ClockTimeline], which sees the exchanges on both sides of each moment.
 */
public class ClockSync(private val window: Int = DEFAULT_WINDOW) {
    init {
        require(window >= 2) { "window must hold at least 2 exchanges: $window" }
    }

    private val t1 = LongArray(window)
    private val t2 = LongArray(window)
    private val t3 = LongArray(window)
    private val t4 = LongArray(window)
    private var start = 0
    private var size = 0
    private val ordered = Array(4) { LongArray(window) }
    private val work = ClockFit(window)

    /** Exchanges refused as self-contradictory. */
    public var refused: Long = 0
        private set

    /** Exchanges accepted in all. */
    public var accepted: Long = 0
        private set

    /** Adds one exchange; returns false (and counts it) when it is refused. */
    public fun add(exchange: ClockExchange): Boolean = add(exchange.t1, exchange.t2, exchange.t3, exchange.t4)

    /** [add] without the object. */
    public fun add(t1: Long, t2: Long, t3: Long, t4: Long): Boolean {
        val last = if (size == 0) Long.MIN_VALUE else this.t1[(start + size - 1) % window]
        if (!ClockFit.consistent(t1, t2, t3, t4) || t1 < last) {
            refused++
            return false
        }
        val i: Int
        if (size < window) {
            i = (start + size) % window
            size++
        } else {
            i = start
            start = (start + 1) % window
        }
        this.t1[i] = t1
        this.t2[i] = t2
        this.t3[i] = t3
        this.t4[i] = t4
        accepted++
        return true
    }

    /** Forgets every exchange (e.g. when the phone's clock is known to have been reset). */
    public fun reset() {
        start = 0
        size = 0
    }

    /**
     * The mapping from the exchanges in the window, referred to its middle (its uncertainty holds
     * there; later times are reached through the drift); null before two exchanges.
     */
    public fun mapping(): ClockMapping? {
        if (size < 2) return null
        for (j in 0 until size) {
            val i = (start + j) % window
            ordered[0][j] = t1[i]
            ordered[1][j] = t2[i]
            ordered[2][j] = t3[i]
            ordered[3][j] = t4[i]
        }
        // Fitted at the window's middle, where both hulls are steadiest; the drift carries it to now.
        val middle = ordered[0][0] + (ordered[3][size - 1] - ordered[0][0]) / 2
        return work.fit(ordered[0], ordered[1], ordered[2], ordered[3], 0, size, middle)
    }

    public companion object {
        /** Ten minutes of exchanges at 4 Hz. */
        public const val DEFAULT_WINDOW: Int = 2400
    }
}

/** The fit of one window of exchanges (arrays sorted by t1), with its own work arrays for up to [capacity] exchanges. */
internal class ClockFit(capacity: Int) {
    private val xu = DoubleArray(capacity)
    private val yu = DoubleArray(capacity)
    private val xd = DoubleArray(capacity)
    private val yd = DoubleArray(capacity)

    /**
     * The mapping from exchanges [from] until [to] of the arrays, referred to laptop time [atNs]:
     * the offset there is the mean of the highest line under the upper bounds and the lowest over
     * the lower bounds; the drift is taken between the window's quarters (a longer base than one
     * hull edge gives).
     */
    fun fit(t1: LongArray, t2: LongArray, t3: LongArray, t4: LongArray, from: Int, to: Int, atNs: Long): ClockMapping? {
        val n = to - from
        if (n < 2) return null
        // Relative to the first exchange on each clock, as doubles (exact for ns over days).
        val base = t1[from]
        val phoneBase = t2[from]
        for (j in 0 until n) {
            val i = from + j
            xu[j] = (t1[i] - base).toDouble()
            yu[j] = ((t2[i] - phoneBase) - (t1[i] - base)).toDouble()
            xd[j] = (t4[i] - base).toDouble()
            yd[j] = ((t3[i] - phoneBase) - (t4[i] - base)).toDouble()
        }
        sortByX(xd, yd, n)
        val hu = hull(xu, yu, n, below = true, hullUp)
        val hd = hull(xd, yd, n, below = false, hullDown)
        val at = (atNs - base).toDouble()
        val uAt = support(xu, yu, hullUp, hu, at)
        val dAt = support(xd, yd, hullDown, hd, at)
        val span = xd[n - 1] - xu[0]
        val q1 = xu[0] + span / 4
        val q3 = xu[0] + span * 3 / 4
        val slope = if (q3 > q1) {
            ((support(xu, yu, hullUp, hu, q3) + support(xd, yd, hullDown, hd, q3)) -
                (support(xu, yu, hullUp, hu, q1) + support(xd, yd, hullDown, hd, q1))) / 2 / (q3 - q1)
        } else {
            0.0
        }
        val offsetAt = (uAt + dAt) / 2 + (phoneBase - base).toDouble()
        val referencePhone = atNs + Math.round(offsetAt)
        // The slope is per laptop ns; per phone ns it is slope / (1 + slope).
        return ClockMapping(referencePhone, offsetAt, slope / (1 + slope) * 1e6, maxOf((uAt - dAt) / 2, 0.0), n)
    }

    private val hullUp = IntArray(capacity)
    private val hullDown = IntArray(capacity)

    /** Insertion sort of the (almost sorted: replies may overtake) downlink points by x. */
    private fun sortByX(x: DoubleArray, y: DoubleArray, n: Int) {
        for (i in 1 until n) {
            val kx = x[i]
            val ky = y[i]
            var j = i - 1
            while (j >= 0 && x[j] > kx) {
                x[j + 1] = x[j]
                y[j + 1] = y[j]
                j--
            }
            x[j + 1] = kx
            y[j + 1] = ky
        }
    }

    /** The lower ([below]) or upper convex hull of the first [n] points (x sorted) into [hull]; returns its size. */
    private fun hull(x: DoubleArray, y: DoubleArray, n: Int, below: Boolean, hull: IntArray): Int {
        val s = if (below) 1.0 else -1.0
        var h = 0
        for (i in 0 until n) {
            if (h > 0 && x[hull[h - 1]] == x[i]) {
                if (s * y[i] < s * y[hull[h - 1]]) h-- else continue
            }
            while (h >= 2) {
                val a = hull[h - 2]
                val b = hull[h - 1]
                val cross = (x[b] - x[a]) * (y[i] - y[a]) - (y[b] - y[a]) * (x[i] - x[a])
                if (s * cross <= 0) h-- else break
            }
            hull[h++] = i
        }
        return h
    }

    /**
     * At [at], the line that is highest (for the lower hull) or lowest (upper hull) there while on
     * the right side of every point: the hull's edge over [at] (the first or last beyond the
     * points' span); the point's own value when all points share one x.
     */
    private fun support(x: DoubleArray, y: DoubleArray, hull: IntArray, h: Int, at: Double): Double {
        if (h == 1) return y[hull[0]]
        var e = 0
        while (e < h - 2 && x[hull[e + 1]] < at) e++
        val a = hull[e]
        val b = hull[e + 1]
        return y[a] + (y[b] - y[a]) / (x[b] - x[a]) * (at - x[a])
    }

    companion object {
        /** Whether an exchange's times agree with themselves: each way forwards, the phone's part within the round trip. */
        fun consistent(t1: Long, t2: Long, t3: Long, t4: Long): Boolean = t4 >= t1 && t3 >= t2 && (t3 - t2) <= (t4 - t1)
    }
}

/**
 * A recording's phone clock on the laptop's, from every exchange made while it ran: each moment is
 * mapped with the exchanges within [halfWindowNs] on both sides of it (laptop time), so neither
 * the start nor a change of drift is extrapolated. Anchors every [stepNs] of laptop time, linear
 * between them. Exchanges that contradict themselves are left out ([refused]).
 */
public class ClockTimeline(exchanges: List<ClockExchange>, halfWindowNs: Long = 150_000_000_000, stepNs: Long = 1_000_000_000) {
    private val anchorsPhone: LongArray
    private val anchorsOffset: DoubleArray
    private val anchorsUncertainty: DoubleArray

    /** Exchanges left out as self-contradictory. */
    public val refused: Int

    /** How many exchanges the timeline rests on. */
    public val exchanges: Int

    init {
        require(halfWindowNs > 0 && stepNs > 0) { "window and step must be > 0" }
        val kept = exchanges.filter { ClockFit.consistent(it.t1, it.t2, it.t3, it.t4) }.sortedBy { it.t1 }
        refused = exchanges.size - kept.size
        this.exchanges = kept.size
        require(kept.size >= 2) { "a clock timeline needs at least 2 consistent exchanges, got ${kept.size}" }
        val t1 = LongArray(kept.size) { kept[it].t1 }
        val t2 = LongArray(kept.size) { kept[it].t2 }
        val t3 = LongArray(kept.size) { kept[it].t3 }
        val t4 = LongArray(kept.size) { kept[it].t4 }
        val fit = ClockFit(kept.size)
        val first = t1.first()
        val last = t4.last()
        val count = ((last - first) / stepNs + 2).toInt()
        val phone = LongArray(count)
        val offset = DoubleArray(count)
        val uncertainty = DoubleArray(count)
        var lo = 0
        var hi = 0
        for (k in 0 until count) {
            val at = first + k * stepNs
            while (lo < kept.size - 2 && t1[lo] < at - halfWindowNs) lo++
            while (hi < kept.size && t1[hi] <= at + halfWindowNs) hi++
            val to = maxOf(hi, lo + 2)
            // Near the recording's ends the window is one-sided: fit at its middle, carried to the anchor by the drift.
            val middle = t1[lo] + (t4[to - 1] - t1[lo]) / 2
            val m = fit.fit(t1, t2, t3, t4, lo, to, middle)!!
            val o = m.offsetAt(at + Math.round(m.offsetNs))
            phone[k] = at + Math.round(o)
            offset[k] = o
            uncertainty[k] = m.uncertaintyNs + Math.abs(m.driftPpm) * 1e-6 * Math.abs(at - middle)
        }
        anchorsPhone = phone
        anchorsOffset = offset
        anchorsUncertainty = uncertainty
    }

    /** The offset (phone − laptop, ns) at phone time [phoneNs], linear between anchors, constant drift beyond. */
    public fun offsetAt(phoneNs: Long): Double = interpolate(anchorsOffset, phoneNs)

    /** The error bound at phone time [phoneNs], ns (see [ClockMapping.uncertaintyNs]). */
    public fun uncertaintyAt(phoneNs: Long): Double = interpolate(anchorsUncertainty, phoneNs, extrapolate = false)

    /** Phone time [phoneNs] on the laptop's clock, ns. */
    public fun toLaptop(phoneNs: Long): Long = phoneNs - Math.round(offsetAt(phoneNs))

    /** Laptop time [laptopNs] on the phone's clock, ns (the inverse of [toLaptop] to within a nanosecond). */
    public fun toPhone(laptopNs: Long): Long {
        var p = laptopNs + Math.round(anchorsOffset[0])
        repeat(3) { p = laptopNs + Math.round(offsetAt(p)) }
        return p
    }

    /** The phone times the timeline spans (its first and last anchors). */
    public val firstPhoneNs: Long get() = anchorsPhone.first()
    public val lastPhoneNs: Long get() = anchorsPhone.last()

    private fun interpolate(values: DoubleArray, phoneNs: Long, extrapolate: Boolean = true): Double {
        val n = anchorsPhone.size
        var i = java.util.Arrays.binarySearch(anchorsPhone, phoneNs)
        if (i >= 0) return values[i]
        i = -i - 1 // first anchor after phoneNs
        val a = when {
            i <= 0 -> 0
            i >= n -> n - 2
            else -> i - 1
        }
        val b = a + 1
        val f = (phoneNs - anchorsPhone[a]).toDouble() / (anchorsPhone[b] - anchorsPhone[a]).toDouble()
        if (!extrapolate && (f < 0 || f > 1)) return values[if (f < 0) a else b]
        return values[a] + (values[b] - values[a]) * f
    }
}
