package dev.motionfusion.cli

import dev.motionfusion.core.event.SampleRate
import java.util.Locale

/**
 * Running statistics of an IMU table: constant memory for any length. Means skip
 * non-finite values (counted separately); the rate is SampleRate's (gaps left out, and counted).
 */
internal class TableStats(private val hasMagnetometer: Boolean) {
    var samples = 0L
        private set
    private var firstT = Double.NaN
    private var lastT = Double.NaN
    private var minT = Double.POSITIVE_INFINITY
    private var maxT = Double.NEGATIVE_INFINITY
    private var backwards = 0L
    private var repeated = 0L
    private val rate = SampleRate()
    private val sums = DoubleArray(AXES.size)
    private val counts = LongArray(AXES.size)
    private var nonFinite = 0L

    /** One row: [timeS] and [row] = gx, gy, gz, ax, ay, az, mx, my, mz. */
    fun add(timeS: Double, row: DoubleArray) {
        if (samples == 0L) firstT = timeS else {
            val dt = timeS - lastT
            if (dt < 0) backwards++ else if (dt == 0.0) repeated++
        }
        lastT = timeS
        minT = minOf(minT, timeS)
        maxT = maxOf(maxT, timeS)
        rate.add(Math.round(timeS * 1e9))
        samples++
        for (a in 0 until if (hasMagnetometer) 9 else 6) accumulate(a, row[a])
    }

    private fun accumulate(axis: Int, v: Double) {
        if (v.isFinite()) {
            sums[axis] += v
            counts[axis]++
        } else {
            nonFinite++
        }
    }

    fun report(name: String): String = buildString {
        val duration = if (samples > 1) lastT - firstT else 0.0
        appendLine("file        $name")
        appendLine("samples     $samples")
        appendLine(f("duration    %.3f s", duration) + if (samples > 1 && (minT != firstT || maxT != lastT)) f(" (times span %.3f s: rows out of order)", maxT - minT) else "")
        if (rate.hz.isFinite()) appendLine(f("rate        %.3f Hz", rate.hz))
        if (rate.gaps > 0) appendLine(f("gaps        %d, the longest %.3f s (left out of the rate)", rate.gaps, rate.longestGapNs * 1e-9))
        appendLine("timestamps  $backwards backwards, $repeated repeated")
        if (nonFinite > 0) appendLine("non-finite  $nonFinite values (NaN or infinite; not in the means)")
        appendLine("means")
        val shown = if (hasMagnetometer) AXES.size else 6
        for (a in 0 until shown) {
            val mean = if (counts[a] > 0) sums[a] / counts[a] else Double.NaN
            appendLine(f("  %-3s %12.6f %s", AXES[a], mean, UNITS[a / 3]))
        }
        if (!hasMagnetometer) appendLine("  (no magnetometer columns)")
    }

    private fun f(format: String, vararg args: Any): String = String.format(Locale.ROOT, format, *args)

    private companion object {
        val AXES = listOf("gx", "gy", "gz", "ax", "ay", "az", "mx", "my", "mz")
        val UNITS = listOf("rad/s", "m/s²", "µT")
    }
}
