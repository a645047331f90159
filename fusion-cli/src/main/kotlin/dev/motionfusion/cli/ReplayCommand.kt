package dev.motionfusion.cli

import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.offline.OfflineSettings
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayCsvWriter
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import dev.motionfusion.core.replay.Retimed
import java.io.BufferedOutputStream
import java.io.PrintStream
import java.util.Locale
import java.util.zip.GZIPOutputStream

/** `fusion replay INPUT [-o OUT] [filter settings]`. */
internal class ReplayCommand(
    private val err: PrintStream,
    private val outputs: Outputs,
    /** The rows' time of a timestamp, s (one input of --align, given by [Batch]); null: seconds since the input's origin. */
    private val rowTime: ((Long) -> Double)? = null,
) : Command {
    override val name = "replay"
    override val summary = "run the filter over a recording and write the orientation as CSV"
    override val help = """
        |Usage: fusion replay INPUT [-o OUT.csv[.gz]] [filter settings]
        |       fusion replay INPUT... -o FOLDER/ [filter settings]
        |       fusion replay INPUT INPUT... -o FOLDER/ --align auto|link|gyro|utc [--max-lag S]
        |
        |Merges the recording's streams by timestamp, runs the Madgwick filter over them
        |(accelerometer and magnetometer held, one step per gyroscope sample) and writes CSV,
        |one row per gyroscope sample:
        |  ${ReplayCsvWriter.HEADER}
        |t_s: seconds since the start of the recording (a session's start anchor; the table's
        |own t_s for IMU tables and phyphox). q: sensor → East-North-Up, Hamilton, scalar first.
        |Android azimuth/pitch/roll as SensorManager.getOrientation; aerospace yaw/pitch/roll
        |(Z-Y-X) of the phone as an aircraft (nose = top edge, belly = back); degrees. Linear
        |acceleration in ENU, m/s² (gravity 9.80665 removed). Rows before the filter has an
        |orientation hold NaN.
        |
        |INPUT is recognised by content:
        |  a session folder or zip (docs/SESSION_FORMAT.md)
        |  a plain IMU table t_s,gx,gy,gz,ax,ay,az[,mx,my,mz] (s, rad/s, m/s², µT; .csv or .csv.gz),
        |    or a folder holding input.csv[.gz] (a BROAD trial)
        |  a phyphox export (zip, folder or single CSV) or a Sensor Logger export (zip or folder),
        |    Android or iOS (sign and units from Metadata.csv, else --platform); see docs/IMPORT.md
        |  the IMU of an EuRoC (ASL) folder (mav0/imu0/data.csv; mav0/mag0/data.csv too, as fusion
        |    export writes it) or of a Kalibr imu0.csv (timestamp,omega_x,…,alpha_z), or that file
        |    alone: times in ns of their own clock (t_s from the first row), so public VIO data
        |    sets and fusion export's output replay as they come
        |One input is one recording: a folder holding several is an error that lists them.
        |What an import assumed (a platform, a file left out) is printed as a note.
        |
        |Options:
        |  -o, --output FILE    write there (gzip if it ends in .gz) instead of standard output (- is standard output)
        |  --rows FILE          also write the rows the filter stepped on, one per output row, as
        |                       an IMU table t_s,gx,gy,gz,ax,ay,az[,mx,my,mz] (gzip if it ends in
        |                       .gz): each gyroscope sample with the accelerometer and magnetometer
        |                       readings held at that instant (NaN before the first), so another
        |                       filter can be run on exactly the same samples (docs/ACCURACY.md)
        |  --quiet              no summary and no notes on standard error (warnings and errors still)
        |  --calibration FILE   apply a calibration of fusion calibrate (docs/CALIBRATION.md); one that
        |                       cannot be right (matrix not symmetric positive definite, offsets beyond
        |                       any phone's) is refused naming the file; a note names the device it was
        |                       fitted on when the session was recorded on another
        |  --calibration recorded   apply the calibration in the session's meta.json, whether
        |                       or not the live filter used it
        |  --calibration none   apply none: the raw readings as recorded
        |                       Default: as the live filter did: a session whose meta.json says
        |                       the phone's calibration was applied live is replayed with it (a
        |                       note says so), so the output reproduces its orientation.csv
        |${HeadingOptions.HELP}
        |${FilterOptions.HELP}
        |${InputOptions.HELP}
        |Several inputs (or one with -o ending in /): each is replayed as if alone into
        |FOLDER/NAME.csv (NAME: the input's name without .csv, .csv.gz, .zip), in parallel, one
        |input per available core; one result line per input and a summary on standard error. A bad
        |input gets its message and exit code there and the others go on; the exit code is the
        |worst. Two inputs of the same name, or an output onto an input, are refused first, before
        |the folder is made; a FOLDER that does not exist must be given with its final / (two
        |inputs with -o OUT.csv are refused, not made a folder OUT.csv/); a folder the run made
        |and nothing was written into is removed again.
        |Temporary files (NAME written aside as .NAME.PID-HEX.tmp, a spooled standard input) are
        |removed when fusion is ended by a signal (SIGTERM, Ctrl-C); those of a run that was
        |killed outright (SIGKILL) are removed by the next run writing the same output, or
        |reading standard input, with a note.
        |A progress bar is drawn on standard error when it is a terminal.
        |
        |On one timeline (recordings of several phones, docs/SYNC.md):
        |  --align METHOD       the rows of every INPUT on the first INPUT's clock, as 'fusion align'
        |                       puts them there (METHOD auto, link, gyro or utc; see fusion align --help):
        |                       t_s is then seconds since the first INPUT's origin, for every output.
        |                       The filter runs on each recording's own timestamps; only t_s changes.
        |                       FOLDER/alignment.csv gets fusion align's CSV: each input's method,
        |                       offset, drift and uncertainty_ns, the bound on its rows' times (link: the
        |                       clock exchanges' bound over the whole input; gyro: one sample period of the
        |                       slower phone; utc: empty, as good as the phones' wall clocks). Inputs that
        |                       cannot be aligned (no shared clock exchanges, wall clocks or motion that
        |                       singles one offset out) are refused before anything is written.
        |  --max-lag S          the gyroscopes' search range, as fusion align's
        |The output is written aside and moved into place only when the replay succeeds; an
        |output that is the input or lies inside it is refused.
        |Exit codes: 0 ok, 1 malformed input (FILE:LINE:COLUMN: reason), 2 usage, 3 file not found/unwritable.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val valued = setOf("-o", "--output", "--calibration", "--rows", "--align", "--max-lag") + FilterOptions.VALUED + InputOptions.VALUED + HeadingOptions.VALUED
        val o = Options(args, valued, setOf("--quiet") + FilterOptions.FLAGS)
        if (o.positional.isEmpty()) throw UsageException("replay needs an INPUT")
        val target = o.value("-o") ?: o.value("--output")
        if (o.positional.size > 1 && target == STDOUT) throw UsageException("-o - writes one replay to standard output; with several inputs give -o FOLDER/")
        if (o.positional.size > 1 || (target != null && target.endsWith("/"))) {
            return batch(args, o, valued, target ?: throw UsageException("with several inputs give -o FOLDER/ for their outputs"))
        }
        if (o.value("--align") != null) throw UsageException("--align puts several recordings on one timeline: give two or more INPUTs and -o FOLDER/")
        if (o.value("--max-lag") != null) throw UsageException("--max-lag goes with --align")
        val input = o.positional.single()
        FilterOptions.settings(o) // usage errors before the input is opened
        val heading = HeadingOptions.spec(o)
        val offline = FilterOptions.offline(o)
        // "-o -" is standard output, as without -o.
        val output = (o.value("-o") ?: o.value("--output")).takeUnless { it == STDOUT }
        val file = calibrationFile(o)
        InputOptions.open(input, o, err, name).use { rec ->
            val settings = FilterOptions.settings(o, rec, err, name)
            val calibration = calibration(o, file, rec, err, name)
            val total = rec.metadata?.streams?.values?.sumOf { it.samples }
            val progress = Progress(err, "replay", total)
            val stream = if (output == null) StdoutGuard(out) else BufferedOutputStream(outputs.file(output, listOf(input)), 1 shl 16).let {
                if (output.endsWith(".gz")) GZIPOutputStream(it, 1 shl 16) else it
            }
            // With a second core the rows are formatted while the next ones are read (the same bytes).
            val writer = ReplayCsvWriter(stream, closeStream = output != null, parallel = Runtime.getRuntime().availableProcessors() > 1)
            val replayer = Replayer(settings)
            val rowsFile = o.value("--rows")
            val rows = rowsFile?.let { ImuTableWriter(outputs.file(it, listOf(input)), it.endsWith(".gz"), rec.hasMagnetometer) }
            val counts = rows.use { r ->
                writer.use { w ->
                    val plain = if (r == null) w else object : ReplayListener {
                        override fun step(step: ReplayStep) {
                            w.step(step)
                            r.row(step.timeS, step.angularVelocity, step.specificForce, step.magneticField)
                        }

                        override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) = w.reference(stream, timestampNs, values)
                    }
                    val timed = rowTime?.let { Retimed(plain, it) } ?: plain
                    val tare = HeadingOptions.wrap(heading, timed, rec.name) { probe -> replay(rec, calibration, settings, offline, probe, null) }
                    val counts = replay(rec, calibration, settings, offline, tare ?: timed, progress::update, replayer)
                    if (tare != null && !o.has("--quiet")) err.println("fusion replay: note: ${rec.name}: ${HeadingOptions.note(heading!!, tare)}")
                    counts
                }
            }
            progress.finish()
            if (!o.has("--quiet")) {
                val d = replayer.filter.diagnostics()
                err.println(
                    "fusion replay: ${rec.format.description} ${rec.name}: ${counts.events} events, ${writer.rows} rows " +
                        "(${counts.gyroscope} gyroscope, ${counts.accelerometer} accelerometer, ${counts.magnetometer} magnetometer); " +
                        "skipped: ${d.skippedBeforeInit} before start, ${d.skippedTimestamp} bad timestamps, ${d.skippedGap} after gaps, " +
                        "${d.skippedOutOfRange} beyond any phone's range, ${d.skippedNonFinite} not finite, ${d.skippedZero} zero" +
                        d.magnetometerOffset.takeIf { it.norm() > 0.0 }?.let { m ->
                            String.format(Locale.ROOT, "; the magnetometer's hard-iron offset (%.1f, %.1f, %.1f) µT estimated and taken off", m.x, m.y, m.z)
                        }.orEmpty(),
                )
            }
            // A field whose heading errors persist along the recording, as a building's do (Replayer.fieldPersistenceDeg): the magnetic trust is for that.
            val stray = replayer.fieldPersistenceDeg
            if (!o.has("--quiet") && settings.magTrustSpread == null && stray > OfflineSettings.BUILDING_PERSISTENCE_DEG) {
                err.println(
                    String.format(
                        Locale.ROOT,
                        "fusion replay: note: %s: the field's heading departs from the gyroscope's by a median of %.1f° once a minute's drift is " +
                            "taken out (the rooms measured stay under 7°, most walks through buildings go over): a field that misleads, or a gyroscope " +
                            "that does (violent motion); %son a walk through buildings --set magTrustSpread=%s keeps such a field out of the heading " +
                            "(docs/ACCURACY.md, \"Does the recording look like a building?\")",
                        rec.name, stray,
                        if (offline != null && replayer.offlineWithoutMotionBias) "the offline estimate learnt no gyroscope bias in motion from it; " else "",
                        FilterSettings.BUILDINGS_TRUST_SPREAD,
                    ),
                )
            }
            // A raw magnetometer (a hard-iron offset of hundreds of µT) reads beyond any earth field, and the filter leaves it out.
            replayer.filter.diagnostics().let { d ->
                if (counts.magnetometer > 0 && d.magneticRejections * 2 > d.gyroscopeSteps) {
                    err.println(
                        "fusion replay: warning: ${rec.name}: the magnetometer was left out in ${d.magneticRejections} of ${d.gyroscopeSteps} steps " +
                            "(a field stronger than any earth field, as an uncalibrated magnetometer reads, or a disturbed one): " +
                            "heading there is the gyroscope's alone, as with --mode IMU; a hard-iron calibration makes the field usable " +
                            "(fusion calibrate, then --calibration FILE; docs/CALIBRATION.md)",
                    )
                }
            }
            // A session's meta.json counts each stream's samples on close: a stream file that holds another number lost rows or was replaced.
            rec.metadata?.takeIf { it.complete && calibration == null }?.streams?.let { listed ->
                for ((stream, read) in listOf(SessionStream.GYROSCOPE to counts.gyroscope, SessionStream.ACCELEROMETER to counts.accelerometer, SessionStream.MAGNETOMETER to counts.magnetometer)) {
                    val expected = listed[stream]?.samples ?: continue
                    if (expected != read) {
                        err.println("fusion replay: warning: ${rec.name}: meta.json counts $expected ${stream.key} samples, but ${stream.key}.csv holds $read: " +
                            "the output covers only the samples the file holds (a file cut short or replaced?)")
                    }
                }
            }
            if (counts.gyroscope == 0L) {
                err.println("fusion replay: ${rec.name} has no gyroscope samples: nothing to replay")
                return ExitCode.DATA_ERROR
            }
        }
        return ExitCode.OK
    }

    companion object {
        /** Where --align writes the alignment in the output folder. */
        const val ALIGNMENT_FILE = "alignment.csv"

        /** One replay of [rec] into [listener] (with [replayer], else a new one), as every command runs it. */
        fun replay(
            rec: Recording, calibration: Calibration?, settings: dev.motionfusion.core.filter.FilterSettings, offline: dev.motionfusion.core.filter.offline.OfflineSettings?,
            listener: ReplayListener, progress: ((Long) -> Unit)?, replayer: Replayer = Replayer(settings),
        ): dev.motionfusion.core.replay.ReplayCounts =
            CalibrateCommand.calibrated(rec, calibration, settings).use { e ->
                if (offline == null) replayer.run(e, rec.originNs, listener, progress, rec.name)
                else replayer.runOffline(e, rec.originNs, listener, progress, rec.name, offline)
            }

        /** The calibration file named by --calibration (not `recorded` or `none`), read before the input is opened. */
        fun calibrationFile(o: Options): Calibration? =
            o.value("--calibration")?.let { if (it == "recorded" || it == "none") null else CalibrateCommand.read(InputOptions.path(it)) }

        /**
         * The calibration a replay of [rec] applies under --calibration ([file]: the one it names), checked to
         * apply to [rec]: by default the one the live filter used (a note on [err] unless --quiet).
         */
        fun calibration(o: Options, file: Calibration?, rec: Recording, err: PrintStream, command: String): Calibration? {
            val option = o.value("--calibration")
            val recorded = rec.metadata?.calibration
            val calibration = when (option) {
                null -> recorded?.takeIf { it.appliedInLiveFilter }?.calibration?.also {
                    if (!o.has("--quiet")) err.println("fusion $command: note: ${rec.name}: applying the calibration the live filter used (meta.json; --calibration none to replay without)")
                }
                "none" -> null
                "recorded" -> recorded?.calibration ?: throw UsageException("--calibration recorded: ${rec.name} has no calibration in its meta.json")
                else -> file
            }
            CalibrateCommand.requireApplies(rec, calibration, if (file != null) option else "${rec.name}: meta.json: calibration")
            if (file != null && !o.has("--quiet")) CalibrateCommand.deviceNote(rec, file, option!!)?.let { err.println("fusion $command: note: $it") }
            return calibration
        }
    }

    /** `fusion replay IN... -o DIR/`: one output per input, DIR/NAME.csv, in parallel (Batch). */
    private fun batch(args: List<String>, o: Options, valued: Set<String>, dir: String): Int {
        if (o.value("--rows") != null) throw UsageException("--rows takes one input; replay the inputs one at a time to keep their rows")
        FilterOptions.settings(o)
        FilterOptions.offline(o)
        val method = o.value("--align")?.let { AlignCommand.method(it, "--align") }
        val maxLag = AlignCommand.maxLag(o)
        if (maxLag != null && method == null) throw UsageException("--max-lag goes with --align")
        if (method != null && o.positional.size < 2) throw UsageException("--align puts several recordings on one timeline: give two or more INPUTs")
        val batch = Batch(name, err)
        val folder = java.nio.file.Path.of(dir)
        // Every check before the folder is made: a refused run creates nothing.
        val outputs = batch.outputs(o.positional, dir, ".csv")
        val sidecar = folder.resolve(ALIGNMENT_FILE).toString()
        if (method != null) {
            outputs.indexOf(sidecar).takeIf { it >= 0 }?.let {
                throw UsageException("${o.positional[it]} would be written to $sidecar, where --align writes the alignment; rename the input or replay it apart")
            }
            // As the outputs: checked against the inputs where the folder exists (a new folder lies in none).
            if (java.nio.file.Files.isDirectory(folder)) Outputs().check(sidecar, o.positional)
        }
        val alignment = method?.let { aligned(o, it, maxLag) }
        val made = !java.nio.file.Files.isDirectory(folder)
        if (made) dev.motionfusion.core.io.AtomicFiles.named(folder) { java.nio.file.Files.createDirectory(folder) }
        try {
            val code = batch(args, o, valued, batch, outputs, alignment)
            // The alignment beside the rows it put on one timeline, when any were written.
            if (alignment != null && outputs.any { java.nio.file.Files.exists(java.nio.file.Path.of(it)) }) {
                val files = Outputs().also { it.note = { n -> err.println("fusion: note: $n") } }
                try {
                    files.file(sidecar, o.positional).use { it.write(alignment.csv().toByteArray()) }
                    files.commit()
                } finally {
                    files.abort()
                }
            }
            return code
        } finally {
            // A folder this run made and no input succeeded into is removed again.
            if (made) runCatching { java.nio.file.Files.delete(folder) }
        }
    }

    /**
     * The inputs on the first one's clock by [method] (the aligner of fusion align), with a line on standard error for
     * each; inputs that cannot be aligned are refused.
     */
    private fun aligned(o: Options, method: String, maxLag: Double?): Aligner.Result {
        val result = Aligner(err, name).align(o.positional, o, method, maxLag)
        val ref = result.reference
        result.aligned.firstOrNull { !it.certain }?.let {
            throw dev.motionfusion.core.io.DataFormatException(
                it.input.name, 0, 0,
                "cannot be put on ${ref.name}'s timeline: " + (if (method == "auto") "no clock exchanges with the same laptop, no wall-clock anchors on both, and " else "") +
                    "the gyroscopes show no shared motion that singles one offset out (shake the phones together once, irregularly, while all record); " +
                    "replay without --align to keep each recording's own time",
            )
        }
        for (a in result.aligned.drop(1)) {
            val bound = if (a.uncertaintyNs.isNaN()) "uncertainty not known (the phones' wall clocks: network time is typically within tens of ms)"
            else "± %.3f ms".format(java.util.Locale.ROOT, a.uncertaintyNs / 1e6)
            val offset = "%.6f".format(java.util.Locale.ROOT, a.offsetNs / 1e9)
            err.println("fusion replay: ${a.input.name} on ${ref.name}'s timeline: ${a.method}, offset $offset s, $bound")
        }
        return result
    }

    private fun batch(args: List<String>, o: Options, valued: Set<String>, batch: Batch, outputs: List<String>, alignment: Aligner.Result?): Int {
        // The options without the inputs and -o, for each input's own run.
        val rest = ArrayList<String>()
        var i = 0
        var onlyPositional = false
        while (i < args.size) {
            val a = args[i]
            val optionName = a.substringBefore('=')
            when {
                onlyPositional || !a.startsWith("-") || a == "-" -> Unit
                a == "--" -> onlyPositional = true
                optionName == "-o" || optionName == "--output" || optionName == "--align" || optionName == "--max-lag" -> if (!a.contains('=')) i++
                optionName in valued -> { rest += a; if (!a.contains('=')) rest += args[++i] }
                else -> rest += a
            }
            i++
        }
        // The input after "--", so that one whose name starts with "-" is read as an input in its own run too.
        val origin = alignment?.reference?.originNs
        val jobs = o.positional.mapIndexed { k, input ->
            val rowTime = alignment?.aligned?.get(k)?.let { a -> { t: Long -> Replayer.secondsBetween(origin!!, a.toReference(t)) } }
            Batch.Job(input, outputs[k], rest + listOf("-o", outputs[k], "--", input), rowTime)
        }
        return batch.run(jobs) { r ->
            val m = r.messages.lineSequence().filter { it.isNotBlank() }.joinToString("\n  ")
            if (r.code == ExitCode.OK) "fusion replay: ${r.input} → ${r.value!!.output}" + (if (m.isEmpty()) "" else "\n  $m")
            else "fusion replay: ${r.input}: failed (exit ${r.code}): ${Batch.lastLine(r.messages)}"
        }
    }
}
