/*
 * Runs the filter over trials and scores it with BROAD's metric. The filter outputs ENU, the
 * frame of BROAD's truth. This is the API behind `fusion eval`.
 */
package dev.motionfusion.core.eval

import dev.motionfusion.core.WorldFrame
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.MadgwickFilter
import dev.motionfusion.core.input.ImuTableEvents
import dev.motionfusion.core.input.ImuTableReader
import dev.motionfusion.core.filter.offline.OfflineSettings
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import java.io.File
import kotlin.math.roundToLong

/** The score of one trial. */
public data class TrialResult(val trial: String, val error: ErrorRmse)

public object Evaluation {
    /**
     * Runs the filter over [trial], streaming: [onStep] gets, after each row, the filter's ENU
     * orientation (identity before initialisation; arrays reused) and the row's truth and scored flag.
     */
    public fun run(trial: Trial, settings: FilterSettings, onStep: (estimate: DoubleArray, truth: DoubleArray, scored: Boolean) -> Unit) {
        val filter = MadgwickFilter(settings.copy(outputFrame = WorldFrame.ENU))
        val q = DoubleArray(4)
        trial.open().use { rows ->
            val r = rows.imu
            while (rows.next()) {
                val t = (rows.timeS * 1e9).roundToLong()
                if (rows.hasMag && ImuTableReader.hasMagnetometerReading(r)) {
                    filter.update(t, r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8])
                } else if (rows.hasMag) {
                    // No reading at this instant: the last one is held, as the replay holds it.
                    filter.updateAccelerometer(t, r[3], r[4], r[5])
                    filter.updateGyroscope(t, r[0], r[1], r[2])
                } else {
                    filter.update(t, r[0], r[1], r[2], r[3], r[4], r[5])
                }
                filter.orientationInto(q)
                onStep(q, rows.truth, rows.scored)
            }
        }
    }

    /**
     * Scores [settings] on [trial]; a 6D filter, a trial without magnetometer, a trial scored so by its
     * meta.json ([Trial.headingOffsetScored]) or [headingOffset] has its heading offset removed, which
     * takes a first pass over the trial to find the offset.
     */
    @JvmOverloads
    public fun evaluate(trial: Trial, settings: FilterSettings, offline: OfflineSettings? = null, headingOffset: Boolean = false): TrialResult {
        val sixD = headingOffset || settings.mode == FilterMode.IMU || !trial.hasMag || trial.headingOffsetScored
        return TrialResult(
            trial.name,
            BroadMetric.streamed(sixD) { add -> if (offline == null) run(trial, settings, add) else runOffline(trial, settings, offline, add) },
        )
    }

    /**
     * [run] with the offline estimate (Replayer.runOffline) in place of the causal one: [onStep] gets
     * the rows in order once the whole trial has been read (orientation NaN where no pass has one yet).
     */
    public fun runOffline(trial: Trial, settings: FilterSettings, offline: OfflineSettings, onStep: (estimate: DoubleArray, truth: DoubleArray, scored: Boolean) -> Unit) {
        trial.open().use { rows ->
            val listener = object : ReplayListener {
                override fun step(step: ReplayStep) {
                    rows.next()
                    onStep(step.orientation, rows.truth, rows.scored)
                }
            }
            ImuTableEvents(ImuTableReader.open(trial.input.toPath())).use { events ->
                Replayer(settings).runOffline(events, null, listener, null, trial.name, offline)
            }
        }
    }

    /** Scores every trial under [paths] (see [findTrials]), in name order. */
    internal fun evaluateAll(paths: List<File>, settings: FilterSettings, offline: OfflineSettings? = null): List<TrialResult> =
        findTrials(paths).map { evaluate(Trial.load(it), settings, offline) }

    /**
     * The trial folders under [paths]: each path is a trial folder or a folder of trial folders
     * (e.g. the BROAD subset or the full converted dataset), sorted by name.
     */
    public fun findTrials(paths: List<File>): List<File> = paths.flatMap { p ->
        require(p.isDirectory) { "not a directory: $p" }
        if (Trial.isTrial(p)) listOf(p) else (p.listFiles() ?: emptyArray()).filter { it.isDirectory && Trial.isTrial(it) }.sortedBy { it.name }
    }.also { require(it.isNotEmpty()) { "no trial folders in $paths" } }

    /** A Markdown table of [results] (total, heading, inclination RMSE per trial, then the means). */
    public fun table(results: List<TrialResult>): String = buildString {
        appendLine("| trial | total (°) | heading (°) | inclination (°) |")
        appendLine("|---|---|---|---|")
        for (r in results) appendLine("| ${markdownCell(r.trial)} | ${f(r.error.totalDeg)} | ${f(r.error.headingDeg)} | ${f(r.error.inclinationDeg)} |")
        appendLine(
            "| **mean** | **${f(results.map { it.error.totalDeg }.average())}** | ${f(results.map { it.error.headingDeg }.average())} | " +
                "${f(results.map { it.error.inclinationDeg }.average())} |",
        )
    }

    /**
     * The same figures as CSV for scripts: `trial,total_deg,heading_deg,inclination_deg`, one row per trial and no mean
     * row, values to 1e-6°; with [rotationVector] (the phone's own orientation per trial, as [PhoneComparison.table])
     * three more columns `rv_total_deg,rv_heading_deg,rv_inclination_deg`, empty for a trial without one. A trial name
     * with a comma, quote or line break is quoted (RFC 4180).
     */
    @JvmOverloads
    public fun csv(results: List<TrialResult>, rotationVector: Map<String, ErrorRmse> = emptyMap()): String = buildString {
        val rv = rotationVector.isNotEmpty()
        append("trial,total_deg,heading_deg,inclination_deg")
        appendLine(if (rv) ",rv_total_deg,rv_heading_deg,rv_inclination_deg" else "")
        fun cells(e: ErrorRmse?) = if (e == null) ",," else "${c(e.totalDeg)},${c(e.headingDeg)},${c(e.inclinationDeg)}"
        for (r in results) {
            append(csvField(r.trial)).append(',').append(cells(r.error))
            appendLine(if (rv) "," + cells(rotationVector[r.trial]) else "")
        }
    }

    /** [v] for a CSV cell: 6 decimals, empty when NaN. */
    private fun c(v: Double): String = if (v.isNaN()) "" else String.format(java.util.Locale.ROOT, "%.6f", v)

    /** [s] as one CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, quote or line break. */
    private fun csvField(s: String): String =
        if (s.none { it == ',' || it == '"' || it == '\n' || it == '\r' }) s else "\"" + s.replace("\"", "\"\"") + "\""

    private fun f(v: Double) = String.format(java.util.Locale.ROOT, "%.2f", v)

    /** [s] as the text of one Markdown table cell: `|` escaped, line breaks as spaces (a session named `pipe|name`). */
    internal fun markdownCell(s: String): String = s.replace("|", "\\|").replace('\r', ' ').replace('\n', ' ')
}
