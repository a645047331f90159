/*
 * A judgement of a whole recording's magnetometer for heading: how far, and for how long, the field's heading
 * strays from where the gyroscope alone turns (docs/ACCURACY.md, "Does the recording look like a building?").
 * Orientation sensor → ENU, [w, x, y, z]; rad/s, µT, s; the result in degrees.
 */
package dev.motionfusion.core.filter.offline

import kotlin.math.PI
import kotlin.math.abs
import kotlin.math.exp

/**
 * The field's persistent heading error against the gyroscope, over a recording. Fed each filter step: its
 * orientation, the raw gyroscope reading and the field as the filter takes it. It follows z, the field's heading in
 * the frame the gyroscope alone would carry (the heading the field gives minus every correction the filter has
 * applied about the vertical), low-passed over [LOW_PASS_TIME] (a magnet's seconds and a swinging phone's
 * moments average out), and fits a line to it over an exponential window of [LINE_TIME] (so a constant offset and
 * a gyroscope bias drop out). Each fresh reading's departure of low-passed z from that line, once the fit has had
 * [WARM_UP] s, goes into a histogram (memory fixed whatever the length); [median] is that departure's median,
 * degrees. Each reading's share is clipped at [CLIP] from the line (a magnet's field that spins round is no
 * larger error than a wrong one).
 *
 * A building's field errors span tens of metres, so they persist along a walk; a room's, and a magnet's, average
 * out within seconds (the figures per data set: docs/ACCURACY.md). It judges after the fact: the causal filter does not
 * use it; above OfflineSettings.buildingPersistence the offline passes learn no bias in motion, and `fusion replay`
 * suggests the magnetic trust.
 */
internal class FieldPersistence {
    // The heading corrections the filter has made (rad), as HeadingSmoother's u summed.
    private var corrections = 0.0
    private val prev = DoubleArray(4)
    private var havePrev = false
    private var started = false
    private var lowPassed = 0.0
    private var sinceReading = 0.0

    // Time since the line started (at the first reading, and again after a gap).
    private var sinceStart = 0.0

    // The line's exponentially weighted normal equations in τ, the time before now: Σw, Σwτ, Σwτ², Σwz, Σwτz.
    private var s0 = 0.0
    private var s1 = 0.0
    private var s2 = 0.0
    private var sz0 = 0.0
    private var sz1 = 0.0
    private val histogram = LongArray(BINS)
    private var count = 0L

    /**
     * One filter step: orientation [q] after it (NaN before the filter has one), the raw gyroscope reading
     * [wx], [wy], [wz] over the [dt] s since the previous step, [linked] false after a gap; [newReading] when [m]
     * holds a magnetometer reading new at this step, as the filter takes it.
     */
    fun step(q: DoubleArray, linked: Boolean, wx: Double, wy: Double, wz: Double, dt: Double, newReading: Boolean, m: DoubleArray) {
        if (q[0].isNaN()) {
            havePrev = false
            return
        }
        if (havePrev && linked) {
            val u = HeadingSmoother.correction(prev, q, wx, wy, wz, dt)
            if (u.isFinite()) corrections += u
            sinceReading += dt
            sinceStart += dt
        } else if (havePrev) {
            started = false // across a gap the gyroscope's frame is lost: the line starts again
        }
        q.copyInto(prev)
        havePrev = true
        if (!newReading || !HeadingSmoother.usable(m)) return
        val y = HeadingSmoother.magHeading(m, q) - corrections
        if (!started) {
            started = true
            lowPassed = y
            s0 = 0.0; s1 = 0.0; s2 = 0.0; sz0 = 0.0; sz1 = 0.0
            sinceReading = 0.0
            sinceStart = 0.0
        }
        val d = sinceReading
        sinceReading = 0.0
        // The window's origin moves to now (τ → τ − d), then the older readings are forgotten.
        s2 += d * (d * s0 - 2.0 * s1)
        s1 -= d * s0
        sz1 -= d * sz0
        val keep = exp(-d / LINE_TIME)
        s0 *= keep; s1 *= keep; s2 *= keep; sz0 *= keep; sz1 *= keep
        val predicted = line()
        val line = if (predicted.isNaN()) lowPassed else predicted
        val z = line + HeadingSmoother.wrap(y - line).coerceIn(-CLIP, CLIP)
        lowPassed += minOf(1.0, d / LOW_PASS_TIME) * (z - lowPassed)
        s0 += 1.0
        sz0 += lowPassed
        if (sinceStart < WARM_UP) return
        val now = line()
        if (now.isNaN()) return
        val departure = abs(lowPassed - now) * DEGREES
        // Not finite (an orientation or a field that was not): what the line held is lost, so it starts again.
        if (!departure.isFinite()) {
            started = false
            return
        }
        histogram[minOf(BINS - 1, (departure / BIN).toInt())]++
        count++
    }

    /** The line's value now, or NaN while two readings apart in time have not fixed it. */
    private fun line(): Double {
        val det = s0 * s2 - s1 * s1
        return if (s0 > 0.0 && det > 1e-9 * s0 * s0) (s2 * sz0 - s1 * sz1) / det else Double.NaN
    }

    /** The median departure over the recording, degrees (to [BIN]); NaN before [WARM_UP] s of a line. */
    fun median(): Double {
        if (count == 0L) return Double.NaN
        var c = 0L
        for (i in 0 until BINS) {
            c += histogram[i]
            if (2 * c >= count) return (i + 0.5) * BIN
        }
        return BINS * BIN
    }

    companion object {
        const val LOW_PASS_TIME = 5.0
        const val LINE_TIME = 60.0
        const val WARM_UP = 20.0
        val CLIP = 30.0 * PI / 180.0

        private const val DEGREES = 180.0 / PI
        private const val BIN = 0.1
        private const val BINS = 1800
    }
}
