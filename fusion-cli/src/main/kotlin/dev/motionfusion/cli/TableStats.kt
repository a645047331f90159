package dev.motionfusion.cli

import dev.motionfusion.core.io.ImuSample
import java.util.Locale

/**
 * Running statistics of an IMU table: constant memory for any length. Means skip
 * non-finite values (counted separately); the mean rate is (samples − 1) / duration.
 */
internal class TableStats(private val hasMagnetometer: Boolean) {
    var samples = 0L
        private set
    private var firstT = Double.NaN
    private var lastT = Double.NaN
    private var backwards = 0L
    private var repeated = 0L
    private val sums = DoubleArray(AXES.size)
    private val counts = LongArray(AXES.size)
    private var nonFinite = 0L

    fun add(s: ImuSample) {
        if (samples == 0L) firstT = s.timeS else {
            val dt = s.timeS - lastT
            if (dt < 0) backwards++ else if (dt == 0.0) repeated++
        }
        lastT = s.timeS
        samples++
        accumulate(0, s.gx); accumulate(1, s.gy); accumulate(2, s.gz)
        accumulate(3, s.ax); accumulate(4, s.ay); accumulate(5, s.az)
        if (hasMagnetometer) {
            accumulate(6, s.mx); accumulate(7, s.my); accumulate(8, s.mz)
        }
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
        appendLine(f("duration    %.3f s", duration))
        if (samples > 1 && duration > 0) appendLine(f("rate        %.3f Hz (mean)", (samples - 1) / duration))
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
