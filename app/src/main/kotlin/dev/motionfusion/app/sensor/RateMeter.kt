package dev.motionfusion.app.sensor

import kotlin.math.sqrt

/**
 * Achieved rate and jitter of one sensor, from its event timestamps (ns), over the last
 * [window] intervals. Intervals that are zero (duplicate timestamps) or negative (time going
 * backwards) are counted and left out of the statistics. Allocation-free per sample; not
 * thread-safe (one writer thread).
 */
class RateMeter(private val window: Int = 256) {
    private val intervals = LongArray(window)
    private var size = 0
    private var next = 0
    private var lastNs = 0L
    private var hasLast = false

    /** All timestamps seen. */
    var samples: Long = 0L
        private set

    /** Timestamps equal to the previous one. */
    var duplicates: Long = 0L
        private set

    /** Timestamps earlier than the previous one. */
    var backwards: Long = 0L
        private set

    init {
        require(window >= 2) { "window must hold at least 2 intervals, got $window" }
    }

    fun add(timestampNs: Long) {
        samples++
        if (hasLast) {
            val dt = timestampNs - lastNs
            when {
                dt == 0L -> duplicates++
                dt < 0L -> backwards++
                else -> {
                    intervals[next] = dt
                    next = (next + 1) % window
                    if (size < window) size++
                }
            }
        }
        lastNs = timestampNs
        hasLast = true
    }

    /** Mean rate over the window, Hz; NaN before two timestamps. */
    fun rateHz(): Double {
        if (size == 0) return Double.NaN
        return 1e9 / meanIntervalNs()
    }

    /** Standard deviation of the intervals over the window, ms; NaN before three timestamps. */
    fun jitterMs(): Double {
        if (size < 2) return Double.NaN
        val mean = meanIntervalNs()
        var s = 0.0
        for (i in 0 until size) {
            val d = intervals[i] - mean
            s += d * d
        }
        return sqrt(s / (size - 1)) * 1e-6
    }

    fun reset() {
        size = 0; next = 0; hasLast = false; samples = 0; duplicates = 0; backwards = 0
    }

    private fun meanIntervalNs(): Double {
        var s = 0.0
        for (i in 0 until size) s += intervals[i]
        return s / size
    }
}
