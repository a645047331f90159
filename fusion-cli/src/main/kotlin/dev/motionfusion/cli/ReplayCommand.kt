package dev.motionfusion.cli

import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.replay.ReplayCsvWriter
import dev.motionfusion.core.replay.ReplayListener
import dev.motionfusion.core.replay.ReplayStep
import dev.motionfusion.core.replay.Replayer
import java.io.BufferedOutputStream
import java.io.PrintStream
import java.util.zip.GZIPOutputStream

/** `fusion replay INPUT [-o OUT] [filter settings]`. */
internal class ReplayCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "replay"
    override val summary = "run the filter over a recording and write the orientation as CSV"
    override val help = """
        |Usage: fusion replay INPUT [-o OUT.csv[.gz]] [filter settings]
        |       fusion replay INPUT... -o FOLDER/ [filter settings]
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
        |  -o, --output FILE    write there (gzip if it ends in .gz) instead of standard output
        |  --rows FILE          also write the rows the filter stepped on, one per output row, as
        |                       an IMU table t_s,gx,gy,gz,ax,ay,az[,mx,my,mz] (gzip if it ends in
        |                       .gz): each gyroscope sample with the accelerometer and magnetometer
        |                       readings held at that instant (NaN before the first), so another
        |                       filter can be run on exactly the same samples (docs/ACCURACY.md)
        |  --quiet              no summary on standard error
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
        |The output is written aside and moved into place only when the replay succeeds; an
        |output that is the input or lies inside it is refused.
        |Exit codes: 0 ok, 1 malformed input (FILE:LINE:COLUMN: reason), 2 usage, 3 file not found/unwritable.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val valued = setOf("-o", "--output", "--calibration", "--rows") + FilterOptions.VALUED + InputOptions.VALUED + HeadingOptions.VALUED
        val o = Options(args, valued, setOf("--quiet") + FilterOptions.FLAGS)
        if (o.positional.isEmpty()) throw UsageException("replay needs an INPUT")
        val target = o.value("-o") ?: o.value("--output")
        if (o.positional.size > 1 || (target != null && target.endsWith("/"))) {
            return batch(args, o, valued, target ?: throw UsageException("with several inputs give -o FOLDER/ for their outputs"))
        }
        val input = o.positional.single()
        FilterOptions.settings(o) // usage errors before the input is opened
        val heading = HeadingOptions.spec(o)
        val offline = FilterOptions.offline(o)
        val output = o.value("-o") ?: o.value("--output")
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
            val rows = rowsFile?.let { ImuTableWriter(outputs.file(it, listOf(input)), it.endsWith(".gz"), SessionStream.MAGNETOMETER in rec.streams) }
            val counts = rows.use { r ->
                writer.use { w ->
                    val plain = if (r == null) w else object : ReplayListener {
                        override fun step(step: ReplayStep) {
                            w.step(step)
                            r.row(step.timeS, step.angularVelocity, step.specificForce, step.magneticField)
                        }

                        override fun reference(stream: SessionStream, timestampNs: Long, values: DoubleArray) = w.reference(stream, timestampNs, values)
                    }
                    val tare = HeadingOptions.wrap(heading, plain, rec.name) { probe -> replay(rec, calibration, settings, offline, probe, null) }
                    val counts = replay(rec, calibration, settings, offline, tare ?: plain, progress::update, replayer)
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
                        "${d.skippedOutOfRange} beyond any phone's range, ${d.skippedNonFinite} not finite, ${d.skippedZero} zero",
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
        /** One replay of [rec] into [listener] (with [replayer], else a new one), as every command runs it. */
        fun replay(
            rec: Recording, calibration: Calibration?, settings: dev.motionfusion.core.filter.FilterSettings, offline: dev.motionfusion.core.filter.offline.OfflineSettings?,
            listener: ReplayListener, progress: ((Long) -> Unit)?, replayer: Replayer = Replayer(settings),
        ): dev.motionfusion.core.replay.ReplayCounts =
            CalibrateCommand.calibrated(rec, calibration).use { e ->
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
        val batch = Batch(name, err)
        val folder = java.nio.file.Path.of(dir)
        // Every check before the folder is made: a refused run creates nothing.
        val outputs = batch.outputs(o.positional, dir, ".csv")
        val made = !java.nio.file.Files.isDirectory(folder)
        if (made) dev.motionfusion.core.io.AtomicFiles.named(folder) { java.nio.file.Files.createDirectory(folder) }
        try {
            return batch(args, o, valued, batch, outputs)
        } finally {
            // A folder this run made and no input succeeded into is removed again.
            if (made) runCatching { java.nio.file.Files.delete(folder) }
        }
    }

    private fun batch(args: List<String>, o: Options, valued: Set<String>, batch: Batch, outputs: List<String>): Int {
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
                optionName == "-o" || optionName == "--output" -> if (!a.contains('=')) i++
                optionName in valued -> { rest += a; if (!a.contains('=')) rest += args[++i] }
                else -> rest += a
            }
            i++
        }
        // The input after "--", so that one whose name starts with "-" is read as an input in its own run too.
        val jobs = o.positional.mapIndexed { k, input -> Batch.Job(input, outputs[k], rest + listOf("-o", outputs[k], "--", input)) }
        return batch.run(jobs) { r ->
            val m = r.messages.lineSequence().filter { it.isNotBlank() }.joinToString("\n  ")
            if (r.code == ExitCode.OK) "fusion replay: ${r.input} → ${r.value!!.output}" + (if (m.isEmpty()) "" else "\n  $m")
            else "fusion replay: ${r.input}: failed (exit ${r.code}): ${Batch.lastLine(r.messages)}"
        }
    }
}
