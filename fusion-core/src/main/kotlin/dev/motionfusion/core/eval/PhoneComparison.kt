/*
 * Comparison with the phone's own orientation: a trial folder may hold rotation_vector.csv(.gz)
 * (t_s,qw,qx,qy,qz: the phone's TYPE_ROTATION_VECTOR, sensor → ENU like the truth), as the Tyrex
 * subset does. It is scored with the same metric against the same truth, so the filter's table can
 * show it beside the filter's figures.
 */
package dev.motionfusion.core.eval

import dev.motionfusion.core.input.QuaternionTableReader
import java.io.File
import java.util.Locale
import kotlin.math.abs

public object PhoneComparison {
    /** The rotation-vector file of trial folder [dir], or null. */
    @JvmStatic
    public fun rotationVectorFile(dir: File): File? =
        listOf(File(dir, "rotation_vector.csv.gz"), File(dir, "rotation_vector.csv")).firstOrNull { it.isFile }

    /**
     * BROAD's metric of the rotation vector in [dir] against [trial]'s truth (rows matched by t_s to
     * 1 µs; scored where the truth is), or null without a rotation-vector file. Both tables are
     * streamed: memory does not grow with the trial.
     * @throws dev.motionfusion.core.io.DataFormatException for a malformed file.
     * @throws IllegalArgumentException when no row matches a scored truth row.
     */
    @JvmStatic
    public fun rotationVector(dir: File, trial: Trial): ErrorRmse? {
        val file = rotationVectorFile(dir) ?: return null
        val unknown = doubleArrayOf(Double.NaN, Double.NaN, Double.NaN, Double.NaN)
        val metric = BroadMetric.Accumulator()
        trial.open().use { t ->
            QuaternionTableReader.open(file.toPath()).use { rv ->
                var more = rv.next()
                while (t.next()) {
                    while (more && rv.timeS < t.timeS - 1e-6) more = rv.next()
                    val matched = more && abs(rv.timeS - t.timeS) <= 1e-6
                    metric.add(if (matched) rv.q else unknown, t.truth, t.scored)
                }
            }
        }
        val e = metric.result()
        require(e.samples > 0) { "${file.path}: no row at the time of a scored truth row" }
        return e
    }

    /**
     * The table of [Evaluation.table] with the rotation vector's total, heading and inclination
     * beside the filter's, for the trials named in [rotationVector]; means over the trials that have one.
     */
    @JvmStatic
    public fun table(results: List<TrialResult>, rotationVector: Map<String, ErrorRmse>): String = buildString {
        appendLine("| trial | total (°) | heading (°) | inclination (°) | rotation vector total (°) | heading (°) | inclination (°) |")
        appendLine("|---|---|---|---|---|---|---|")
        for (r in results) {
            val p = rotationVector[r.trial]
            appendLine("| ${Evaluation.markdownCell(r.trial)} | ${f(r.error.totalDeg)} | ${f(r.error.headingDeg)} | ${f(r.error.inclinationDeg)} | ${p?.let { f(it.totalDeg) } ?: ""} | ${p?.let { f(it.headingDeg) } ?: ""} | ${p?.let { f(it.inclinationDeg) } ?: ""} |")
        }
        val with = results.filter { it.trial in rotationVector }
        val rv = with.map { rotationVector.getValue(it.trial) }
        appendLine(
            "| **mean** | **${f(results.map { it.error.totalDeg }.average())}** | ${f(results.map { it.error.headingDeg }.average())} | " +
                "${f(results.map { it.error.inclinationDeg }.average())} | **${f(rv.map { it.totalDeg }.average())}** | ${f(rv.map { it.headingDeg }.average())} | ${f(rv.map { it.inclinationDeg }.average())} |",
        )
        if (with.size < results.size) {
            appendLine(
                "| **mean of the ${with.size} with a rotation vector** | **${f(with.map { it.error.totalDeg }.average())}** | ${f(with.map { it.error.headingDeg }.average())} | " +
                    "${f(with.map { it.error.inclinationDeg }.average())} | | | |",
            )
        }
    }

    private fun f(v: Double) = String.format(Locale.ROOT, "%.2f", v)
}
