package dev.motionfusion.cli

import dev.motionfusion.core.eval.BroadMetric
import dev.motionfusion.core.eval.ErrorRmse
import dev.motionfusion.core.eval.Evaluation
import dev.motionfusion.core.eval.PhoneComparison
import dev.motionfusion.core.eval.StillTilt
import dev.motionfusion.core.eval.Trial
import dev.motionfusion.core.eval.TrialResult
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.input.ImuTableReader
import dev.motionfusion.core.input.QuaternionTableReader
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.filter.offline.OfflineSettings
import dev.motionfusion.core.event.SessionStream
import java.io.File
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path
import kotlin.math.abs

/** `fusion eval`: BROAD's metric, wrapping core eval (BroadMetric, Evaluation, Trial). */
internal class EvalCommand(private val err: PrintStream) : Command {
    override val name = "eval"
    override val summary = "BROAD error metrics against ground truth, per trial and mean"
    override val help = """
        |Usage: fusion eval [filter settings] [--6d] TRIAL_DIR|DATASET_DIR|SESSION ...
        |       fusion eval [--6d] --truth TRUTH.csv[.gz] ORIENTATION.csv[.gz]
        |       fusion eval --rows ROWS.csv[.gz] [--after FROM:TO] ORIENTATION.csv[.gz]
        |
        |BROAD's metric (Laidig et al. 2021): error e = q_est ⊗ q_truth*; total 2·acos|e_w|,
        |heading 2·atan|e_z/e_w|, inclination 2·acos √(e_w² + e_z²); RMSE in degrees over the
        |scored samples (truth column movement = 1; all rows without that column), samples
        |without truth skipped. One constant heading offset per trial is removed before scoring
        |with --6d, for a 6D filter (--mode 6d, or no magnetometer) and for a trial whose
        |meta.json says "scoring": "6d…" (ADVIO's truth has no north). Filter options go with
        |the first form only. Prints a Markdown table: one row per trial, then the mean
        |(--csv: CSV for scripts, trial,total_deg,heading_deg,inclination_deg to 1e-6°, one row per
        |trial, no mean row and no filter line). --quiet: no notes on standard error (warnings and
        |errors still), in every form.
        |Rows are named by trial folder; where two trials share a name (t01 of two data sets) by
        |their paths. A trial without a scored sample is an error, not a row of NaN.
        |A trial folder with rotation_vector.csv[.gz] (t_s,qw,qx,qy,qz: the phone's own
        |orientation, as in the Tyrex subset) also gets that scored, in columns beside the filter's.
        |
        |First form: runs the filter on each trial folder (input.csv[.gz] + truth.csv[.gz], the
        |layout of the BROAD subset and of the public dataset converted to CSV), on each trial
        |folder and session inside DATASET_DIR, and on sessions with a truth.csv stream (fusion
        |simulate). A folder inside DATASET_DIR with only one of input.csv and truth.csv fails
        |in the summary, so that the mean is not silently over fewer trials.
        |The public BROAD dataset's HDF5/MAT files are not read directly: convert them to this
        |layout first.
        |
        |Second form: scores an orientation CSV (e.g. fusion replay's output; columns
        |t_s,qw,qx,qy,qz) against a truth CSV (t_s,qw,qx,qy,qz[,movement]); rows are matched by
        |t_s (to 1 µs); truth rows without an orientation are skipped. Both tables must be in time
        |order (a row before the one above is an error naming it). How many rows were scored is
        |said on standard error (not with --quiet), with a warning when fewer than 90 % of the shorter table's rows
        |match; under 10 % the tables are refused as not aligned in time (e.g. times in ms).
        |  --truth FILE         the truth table
        |  --6d                 remove one constant heading offset before scoring
        |
        |Third form, without ground truth: the tilt check of docs/ACCURACY.md ("Peer figures"):
        |the angle between ORIENTATION's up and the accelerometer of ROWS (an IMU table, e.g.
        |fusion replay --rows), median over the still samples, and with --after also over the
        |samples from FROM to TO s whose |a| is within 0.3 m/s² of g. Rows are matched by t_s
        |(to 1 µs); a row without an orientation is not scored.
        |  --rows FILE          the rows the orientation was computed from
        |  --after FROM:TO      the window after violent motion, s
        |With --csv: still_samples,still_tilt_median_deg,after_motion_samples,
        |after_motion_tilt_median_deg (a median without samples is empty).
        |
        |All inputs are streamed: memory does not grow with their length. Scoring a 6D filter
        |reads each input twice (the first pass finds the heading offset). Several inputs (and a
        |dataset folder's trials) are scored in parallel, one per core, with a progress bar on a
        |terminal; the table lists them in input order. One that fails does not stop the others:
        |it is named with its error and exit code in the summary on standard error, and the exit
        |code is the worst one.
        |
        |${FilterOptions.HELP}
        |${InputOptions.HELP}""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("--truth", "--rows", "--after") + FilterOptions.VALUED + InputOptions.VALUED, setOf("--6d", "--csv", "--quiet") + FilterOptions.FLAGS)
        val csv = o.has("--csv")
        if (o.positional.isEmpty()) throw UsageException("eval needs trial folders, sessions, or --truth TRUTH ORIENTATION")
        val rowsFile = o.value("--rows")
        // Scoring a table that is already an orientation: the options of a replay would do nothing, so they are refused.
        val filterOptions = FilterOptions.VALUED.filter { o.value(it) != null } + FilterOptions.FLAGS.filter { o.has(it) }
        if ((rowsFile != null || o.value("--truth") != null) && filterOptions.isNotEmpty()) {
            throw UsageException("${filterOptions.joinToString(" ")}: ${if (rowsFile != null) "--rows" else "--truth"} scores an orientation table as it is; filter options apply to replays (replay first, or give a trial folder)")
        }
        if (rowsFile != null && (o.value("--truth") != null || o.has("--6d"))) {
            throw UsageException("--rows scores the tilt against the accelerometer; --truth and --6d go with a truth, not with --rows")
        }
        if (rowsFile == null && o.value("--after") != null) throw UsageException("--after goes with --rows")
        if (rowsFile != null) {
            val est = o.positional.singleOrNull() ?: throw UsageException("with --rows give exactly one ORIENTATION file")
            val window = o.value("--after")?.let { w ->
                val v = w.split(':').mapNotNull { it.toDoubleOrNull() }.takeIf { it.size == 2 && w.count { c -> c == ':' } == 1 && it.all { x -> x.isFinite() } }
                    ?: throw UsageException("--after takes FROM:TO in seconds (two finite numbers), not '$w'")
                if (!(v[0] < v[1])) throw UsageException("--after $w: FROM must be before TO")
                v
            }
            val tilt = stillTilt(InputOptions.path(rowsFile), InputOptions.path(est), window, o)
            if (csv) {
                fun c(v: Double) = if (v.isNaN()) "" else String.format(java.util.Locale.ROOT, "%.6f", v)
                out.println("still_samples,still_tilt_median_deg,after_motion_samples,after_motion_tilt_median_deg")
                out.println("${tilt.still.count},${c(tilt.still.percentile(0.5))},${if (window == null) "" else tilt.afterMotion.count},${c(tilt.afterMotion.percentile(0.5))}")
                return ExitCode.OK
            }
            out.println("| still samples | still tilt, median (°) | after-motion samples | after-motion tilt, median (°) |")
            out.println("|---|---|---|---|")
            fun f(v: Double) = if (v.isNaN()) "—" else String.format(java.util.Locale.ROOT, "%.2f", v)
            out.println("| ${tilt.still.count} | ${f(tilt.still.percentile(0.5))} | ${if (window == null) "—" else tilt.afterMotion.count} | ${f(tilt.afterMotion.percentile(0.5))} |")
            return ExitCode.OK
        }
        val truthFile = o.value("--truth")
        if (truthFile != null) {
            val est = o.positional.singleOrNull() ?: throw UsageException("with --truth give exactly one ORIENTATION file")
            val r = scoreTables(InputOptions.path(est), InputOptions.path(truthFile), o.has("--6d"), o, err)
            out.print(if (csv) Evaluation.csv(listOf(r)) else Evaluation.table(listOf(r)))
            return ExitCode.OK
        }
        val settings = FilterOptions.settings(o)
        val offline = FilterOptions.offline(o)
        // One unit per trial folder (a dataset folder expands to its trials) or session, scored in parallel.
        val units = o.positional.flatMap { p -> expand(p) }
        val batch = Batch(name, err)
        val outcomes = batch.map(units, { it.input }) { u, messages ->
            u.error?.let { throw it }
            u.trial?.let { evaluateTrial(it, settings, offline, o.has("--6d")) } ?: (evaluateSession(u.input, settings, offline, o, messages) to null)
        }
        if (outcomes.size == 1 && outcomes[0].code != ExitCode.OK) {
            err.println(outcomes[0].messages)
            return outcomes[0].code
        }
        // Every figure is keyed by the row's label: the trial's name, or its path where two trials share a name.
        val named = outcomes.mapNotNull { it.value?.first?.trial }.groupingBy { it }.eachCount()
        val labelled = outcomes.mapNotNull { r -> r.value?.let { (t, rv) -> t.copy(trial = if (named.getValue(t.trial) > 1) r.input else t.trial) to rv } }
        val results = labelled.map { it.first }
        val rotationVector = labelled.mapNotNull { (t, rv) -> rv?.let { t.trial to it } }.toMap()
        if (results.isNotEmpty() && csv) {
            out.print(Evaluation.csv(results, rotationVector))
        } else if (results.isNotEmpty()) {
            out.println("Filter: ${describe(settings)}" + (offline?.let { ", offline (backward weight ${it.backwardWeight})" } ?: ""))
            out.println()
            out.print(if (rotationVector.isEmpty()) Evaluation.table(results) else PhoneComparison.table(results, rotationVector))
        }
        if (outcomes.size == 1) {
            outcomes[0].messages.takeIf { it.isNotEmpty() }?.let { err.println(it) }
            return ExitCode.OK
        }
        return batch.summary(outcomes) { r ->
            val m = r.messages.lineSequence().filter { it.isNotBlank() }.joinToString("\n  ")
            if (r.code == ExitCode.OK) m.takeIf { it.isNotEmpty() }?.let { "fusion eval: ${r.input}\n  $it" }
            else "fusion eval: ${r.input}: failed (exit ${r.code}): ${Batch.lastLine(r.messages)}"
        }
    }

    /** What one input of eval is: a trial folder ([trial]), a session ([input] alone), or an input that could not be read ([error]). */
    private class Unit(val input: String, val trial: File?, val error: Exception? = null)

    /** [p] as units: a trial folder, each trial folder of a dataset folder, or a session; a folder without trials fails alone. */
    private fun expand(p: String): List<Unit> = try {
        units(p)
    } catch (e: Exception) {
        listOf(Unit(p, null, e))
    }

    private fun units(p: String): List<Unit> {
        val path = InputOptions.path(p)
        if (!Files.exists(path)) throw java.nio.file.NoSuchFileException(p)
        val isTrialSet = Files.isDirectory(path) &&
            (!Files.exists(path.resolve("meta.json")) || Trial.isTrial(path.toFile()))
        if (!isTrialSet) return listOf(Unit(p, null))
        val top = path.toFile()
        if (Trial.isTrial(top)) return listOf(Unit(p, top))
        // A dataset folder: its trial folders, its sessions (folders and zips), and (failed, so that the mean is not silently over fewer)
        // the folders that hold half a trial. Other folders are not recordings and stay out.
        val units = (top.listFiles() ?: emptyArray()).filter { it.isDirectory || it.name.endsWith(".zip", ignoreCase = true) }.sortedBy { it.name }.mapNotNull { d ->
            val halves = listOf("input", "truth").filter { File(d, "$it.csv.gz").isFile || File(d, "$it.csv").isFile }
            when {
                // A zip in a data set is a session (the app's, fusion simulate's); one that is not fails, named.
                d.isFile -> Unit(d.path, null)
                halves.size == 2 -> Unit(d.path, d)
                File(d, "meta.json").isFile -> Unit(d.path, null)
                halves.size == 1 -> {
                    val missing = if (halves[0] == "input") "truth" else "input"
                    Unit(d.path, null, DataFormatException(d.path, 0, 0, "${halves[0]}.csv[.gz] without $missing.csv[.gz]: half a trial, not scored"))
                }
                else -> null
            }
        }
        if (units.isEmpty()) throw DataFormatException(p, 0, 0, "no trial folders (input.csv[.gz] + truth.csv[.gz]), no sessions, and not a session")
        return units
    }

    /** Scores [d], and the phone's rotation vector when the trial has one. */
    private fun evaluateTrial(d: File, settings: FilterSettings, offline: OfflineSettings?, headingOffset: Boolean): Pair<TrialResult, ErrorRmse?> {
        val trial = try {
            Trial.load(d)
        } catch (e: IllegalArgumentException) {
            throw DataFormatException(d.path, 0, 0, e.message ?: "malformed trial")
        }
        val result = Evaluation.evaluate(trial, settings, offline, headingOffset)
        if (result.error.samples == 0) {
            throw DataFormatException(d.path, 0, 0, "no scored sample: no row has both a truth (movement = 1, a known quaternion) and a filter orientation; nothing to score")
        }
        val rv = try {
            PhoneComparison.rotationVector(d, trial)
        } catch (e: IllegalArgumentException) {
            throw DataFormatException(d.path, 0, 0, e.message ?: "rotation vector: no row to score")
        }
        return result to rv
    }

    /**
     * Replays a session with a truth stream and scores every gyroscope step that has truth at its
     * instant; for a 6D score a first replay finds the heading offset.
     */
    private fun evaluateSession(input: String, settings: FilterSettings, offline: OfflineSettings?, o: Options, messages: PrintStream): TrialResult {
        InputOptions.open(input, o, messages, name).use { rec ->
            if (SessionStream.TRUTH !in rec.streams) throw DataFormatException(input, 0, 0, "no truth.csv in this ${rec.format.description}: nothing to score against")
            val sixD = o.has("--6d") || settings.mode == FilterMode.IMU || SessionStream.MAGNETOMETER !in rec.streams
            var steps = 0L
            val e = BroadMetric.streamed(sixD) { add ->
                val lastTruth = DoubleArray(4) { Double.NaN }
                var lastTruthT = Long.MIN_VALUE
                steps = 0L
                val listener = object : ReplayListener {
                    override fun step(step: ReplayStep) {
                        if (lastTruthT != step.timestampNs) return
                        add(step.orientation, lastTruth, true)
                        steps++
                    }

                    override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) {
                        if (stream != SessionStream.TRUTH) return
                        values.copyInto(lastTruth, 0, 0, 4)
                        lastTruthT = timestampNs
                    }
                }
                ReplayCommand.replay(rec, null, settings, offline, listener, null)
            }
            if (steps == 0L) throw DataFormatException(input, 0, 0, "no gyroscope sample has a truth sample at the same timestamp")
            if (e.samples == 0) throw DataFormatException(input, 0, 0, "no scored sample: no gyroscope step has both a known truth and a filter orientation; nothing to score")
            return TrialResult(rec.name, e)
        }
    }

    /** [StillTilt] of the orientation table [estimate] on the IMU table [rows], matched by t_s (to 1 µs). */
    private fun stillTilt(rows: Path, estimate: Path, window: List<Double>?, o: Options): StillTilt {
        val limits = InputOptions.limits(o)
        val tilt = if (window == null) StillTilt() else StillTilt(window[0], window[1])
        val none = DoubleArray(4) { Double.NaN }
        ImuTableReader.open(rows, limits).use { imu ->
            QuaternionTableReader.open(estimate, limits).use { est ->
                var more = est.next()
                var matched = 0L
                val g = DoubleArray(3)
                val a = DoubleArray(3)
                while (imu.next()) {
                    val t = imu.timeS
                    while (more && est.timeS < t - 1e-6) more = est.next()
                    val hit = more && abs(est.timeS - t) <= 1e-6
                    if (hit) matched++
                    imu.row.copyInto(g, 0, 0, 3)
                    imu.row.copyInto(a, 0, 3, 6)
                    tilt.add(t, g, a, if (hit) est.q else none)
                }
                if (matched == 0L) throw DataFormatException(estimate.toString(), 0, 0, "no row's t_s matches a t_s of ${rows.fileName}")
            }
        }
        return tilt
    }

    /** Scores the orientation table [estimate] against [truthPath], both streamed and matched by t_s (to 1 µs). */
    /**
     * Scores the orientation table [estimate] against [truthPath], both streamed and matched by t_s
     * (to 1 µs; both must be in time order, which the reader checks). Says on [err] how many rows
     * were scored; refuses tables that share too few instants to be the same recording's.
     */
    private fun scoreTables(estimate: Path, truthPath: Path, sixD: Boolean, o: Options, err: PrintStream): TrialResult {
        val limits = InputOptions.limits(o)
        var matched = 0L
        var truthRows = 0L
        var estRows = 0L
        val r = BroadMetric.streamed(sixD) { add ->
            matched = 0L
            truthRows = 0L
            estRows = 0L
            QuaternionTableReader.open(estimate, limits).use { est ->
                QuaternionTableReader.open(truthPath, limits).use { truth ->
                    var more = est.next()
                    if (more) estRows++
                    while (truth.next()) {
                        truthRows++
                        val ti = truth.timeS
                        while (more && est.timeS < ti - 1e-6) {
                            more = est.next()
                            if (more) estRows++
                        }
                        if (more && abs(est.timeS - ti) <= 1e-6) {
                            add(est.q, truth.q, truth.scored)
                            matched++
                        }
                    }
                    while (more) {
                        more = est.next()
                        if (more) estRows++
                    }
                }
            }
        }
        val shorter = minOf(truthRows, estRows)
        fun counts() = "$matched of ${truthRows} truth rows and $estRows orientation rows share a t_s (to 1 µs)"
        if (matched == 0L) throw DataFormatException(estimate.toString(), 0, 0, "no row's t_s matches a t_s of ${truthPath.fileName}")
        if (matched * 10 < shorter) {
            throw DataFormatException(estimate.toString(), 0, 0, "${counts()}: the tables are not aligned in time " +
                "(times in another unit, or from another start?); give both t_s in seconds from the same start")
        }
        if (r.samples == 0) throw DataFormatException(truthPath.toString(), 0, 0, "no scored sample with both orientations known")
        if (!o.has("--quiet")) err.println("fusion eval: scored ${r.samples} rows: ${counts()}")
        if (matched * 10 < shorter * 9) err.println("fusion eval: warning: only ${counts()}: the rest is not scored")
        return TrialResult(estimate.fileName.toString(), r)
    }

    private fun describe(s: FilterSettings): String {
        val d = FilterSettings()
        if (s == d) return "defaults (FilterSettings())"
        if (s == FilterSettings.report()) return "the report's settings"
        fun fields(x: FilterSettings) = x.toString().substringAfter('(').removeSuffix(")").split(", ")
        val changed = fields(s) - fields(d).toSet()
        return "defaults with " + changed.joinToString(", ")
    }
}
