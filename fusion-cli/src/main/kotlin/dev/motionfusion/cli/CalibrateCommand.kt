package dev.motionfusion.cli

import dev.motionfusion.core.calib.Calibration
import dev.motionfusion.core.calib.CalibrationJson
import dev.motionfusion.core.calib.CalibrationSettings
import dev.motionfusion.core.calib.Calibrator
import dev.motionfusion.core.calib.EllipsoidModel
import dev.motionfusion.core.export.NoiseConfigs
import dev.motionfusion.core.export.NoiseModel
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.input.Recording
import java.io.PrintStream
import java.nio.charset.StandardCharsets
import java.nio.file.Files
import java.nio.file.Path
import java.util.Locale

/** `fusion calibrate INPUT [-o FILE]`: magnetometer, gyroscope bias and accelerometer calibration (docs/CALIBRATION.md). */
internal class CalibrateCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "calibrate"
    override val summary = "fit magnetometer hard/soft iron, gyroscope bias, accelerometer offset/scale"
    override val help = """
        |Usage: fusion calibrate INPUT [-o FILE.json] [options]
        |
        |Reads a recording (any input of fusion replay) once and fits what it supports:
        |  magnetometer   hard and soft iron (ellipsoid fit), on magnetometer_uncalibrated when
        |                 recorded, else on magnetometer; refused when the field directions cover
        |                 too little of the sphere (turn the phone through all orientations)
        |  gyroscope      bias: the mean rate over still periods (phone untouched on a table)
        |  accelerometer  offset and scale per axis from 6+ still poses (each face up in turn);
        |                 with 12+ distinct poses also the misalignment
        |The result is JSON (docs/CALIBRATION.md) for fusion replay --calibration; each fit's
        |quality (residual, coverage, still time, poses) and each refusal are printed on
        |standard error.
        |
        |Options:
        |  -o, --output FILE    write the JSON there instead of standard output
        |  --min-coverage F    least fraction of the sphere of directions for the magnetometer
        |                       (default ${CalibrationSettings().minCoverage})
        |  --mag-model M        full (hard and soft iron, default) or sphere (hard iron only)
        |  --gravity G          local gravity for the accelerometer, 9.7–9.9 m/s² (default 9.80665)
        |  --quiet              no report on standard error
        |${InputOptions.HELP}
        |Exit codes: 0 at least one sensor calibrated, 1 malformed input or nothing could be
        |calibrated (the reasons are printed), 2 usage, 3 file not found/unwritable.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output", "--min-coverage", "--mag-model", "--gravity") + InputOptions.VALUED, setOf("--quiet"))
        val input = o.positional.singleOrNull() ?: throw UsageException(if (o.positional.isEmpty()) "calibrate needs an INPUT" else "calibrate takes one INPUT")
        val output = o.value("-o") ?: o.value("--output")
        output?.let { outputs.requirePlainFile(it, "the calibration JSON"); outputs.check(it, listOf(input)) }
        val model = when (o.value("--mag-model")?.lowercase() ?: "full") {
            "full" -> EllipsoidModel.FULL
            "sphere" -> EllipsoidModel.SPHERE
            else -> throw UsageException("--mag-model expects full or sphere")
        }
        val d = CalibrationSettings()
        val settings = try {
            CalibrationSettings(magModel = model, minCoverage = o.double("--min-coverage") ?: d.minCoverage, gravity = o.double("--gravity") ?: d.gravity)
        } catch (e: IllegalArgumentException) {
            // The core's message names the setting; say it with the option's name.
            val m = e.message ?: "invalid setting"
            val option = OPTION_OF_SETTING.entries.firstOrNull { m.startsWith(it.key) }
            throw UsageException(if (option == null) m else option.value + m.removePrefix(option.key))
        }
        val calibration = InputOptions.open(input, o, err, name).use { rec ->
            val progress = Progress(err, "calibrate", rec.metadata?.streams?.values?.sumOf { it.samples })
            rec.events().use { e ->
                Calibrator.calibrate(e, rec.streams, settings, "fusion calibrate ${Cli.VERSION}", rec.name, progress::update)
            }.also { progress.finish() }
        }
        if (!o.has("--quiet")) err.print(report(calibration))
        if (calibration.isEmpty) {
            err.println("fusion calibrate: nothing could be calibrated from $input")
            return ExitCode.DATA_ERROR
        }
        val json = CalibrationJson.write(calibration)
        if (output == null) out.print(json) else outputs.file(output, listOf(input)).use { it.write(json.toByteArray(StandardCharsets.UTF_8)) }
        return ExitCode.OK
    }

    private fun report(c: Calibration): String = buildString {
        fun f(v: Double, digits: Int = 3) = String.format(Locale.ROOT, "%.${digits}g", v)
        fun v(x: dev.motionfusion.core.Vector3, digits: Int = 4) = "(${f(x.x, digits)}, ${f(x.y, digits)}, ${f(x.z, digits)})"
        c.magnetometer?.let { m ->
            appendLine("magnetometer (${m.stream.key}, ${m.model.name.lowercase()}): offset ${v(m.correction.offset)} µT, field ${f(m.fieldStrength)} µT, " +
                "residual ${f(m.residualRms)} µT, coverage ${String.format(Locale.ROOT, "%.0f", 100 * m.coverage)} %, " +
                "|B| std ${f(m.magnitudeStdBefore)} → ${f(m.magnitudeStdAfter)} µT over ${m.samples} samples")
        }
        c.gyroscope?.let { g ->
            appendLine("gyroscope (${g.stream.key}): bias ${v(g.bias)} rad/s ± ${v(g.biasStdError, 2)}, still ${f(g.stillTimeS)} s in ${g.stillWindows} windows")
        }
        c.accelerometer?.let { a ->
            appendLine("accelerometer (${a.model.name.lowercase()}, ${a.poses} poses): offset ${v(a.correction.offset)} m/s², " +
                "scale ${v(dev.motionfusion.core.Vector3(a.correction.matrix[0, 0], a.correction.matrix[1, 1], a.correction.matrix[2, 2]), 5)}, residual ${f(a.residualRms)} m/s²")
        }
        for ((sensor, reason) in c.refused) appendLine("$sensor: not calibrated: $reason")
    }

    companion object {
        /** The option of each calibration setting the core's messages name. */
        private val OPTION_OF_SETTING = mapOf("minCoverage" to "--min-coverage", "gravity" to "--gravity", "magModel" to "--mag-model")

        /** Reads a calibration file written by fusion calibrate. */
        fun read(path: Path): Calibration {
            if (Files.isDirectory(path)) throw java.nio.file.FileSystemException(path.toString(), null, "is a folder; --calibration takes a calibration file (fusion calibrate -o FILE.json)")
            val bytes = Files.readAllBytes(path)
            return CalibrationJson.parse(String(bytes, StandardCharsets.UTF_8), path.toString())
        }

        /**
         * A note naming the device [calibration] (from [file]) was fitted on when [rec] was recorded
         * on another one, or when the recording does not say its device; null when they agree or
         * the calibration names none.
         */
        fun deviceNote(rec: Recording, calibration: Calibration, file: String): String? {
            val fitted = calibration.device.substringBefore(';').trim()
            if (fitted.isEmpty()) return null
            val recorded = rec.metadata?.device?.let { "${it.manufacturer} ${it.model}".trim() }.orEmpty()
            return when {
                recorded.isEmpty() -> "$file was fitted on $fitted; ${rec.name} does not say its device: applied as given"
                fitted.equals(recorded, ignoreCase = true) -> null
                else -> "$file was fitted on $fitted, but ${rec.name} was recorded on $recorded: applied as given; its offsets fit that device's sensors, not necessarily these"
            }
        }

        /** Fails with a message naming [file] when [calibration] applies to a stream [rec] does not have. */
        fun requireApplies(rec: Recording, calibration: Calibration?, file: String?) {
            val missing = calibration?.streams()?.filter { it !in rec.streams } ?: return
            if (missing.isNotEmpty()) {
                throw DataFormatException(file ?: "calibration", 0, 0,
                    "applies to ${missing.joinToString(", ") { it.key }}, which ${rec.name} does not have")
            }
        }

        /**
         * The events of [rec] a filter with [settings] steps on (in 6D, the magnetometer's are left out, and not
         * probed), with [calibration] applied when given (check it first with [requireApplies]).
         */
        fun calibrated(rec: Recording, calibration: Calibration?, settings: dev.motionfusion.core.filter.FilterSettings): dev.motionfusion.core.event.SensorEvents {
            val streams = if (settings.mode == dev.motionfusion.core.filter.FilterMode.IMU) rec.streams - dev.motionfusion.core.event.SessionStream.MAGNETOMETER else rec.streams
            return if (calibration == null) rec.events(streams) else dev.motionfusion.core.calib.CalibratedEvents(rec.events(streams), calibration, rec.streams)
        }
    }
}

/** `fusion allan INPUT [-o YAML] [--plot SVG]`: noise characterisation from a long still recording. */
internal class AllanCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "allan"
    override val summary = "Allan deviation of gyroscope and accelerometer; noise figures as kalibr YAML"
    override val help = """
        |Usage: fusion allan INPUT [-o FILE.yaml] [--plot FILE.svg] [--configs DIR]
        |
        |Computes the overlapping Allan deviation per axis of the gyroscope (the uncalibrated
        |stream when recorded) and the accelerometer of a long still recording (the phone
        |untouched for an hour or more; any input of fusion replay), in one pass with memory
        |independent of the length, and reads off the noise terms:
        |  white noise N      line of slope -1/2 at tau = 1 s (angle/velocity random walk)
        |  bias instability B the flat minimum / 0.664
        |  random walk K      line of slope +1/2 at tau = 3 s (rate/acceleration random walk)
        |Writes them as YAML in the layout of kalibr's imu.yaml (accelerometer_noise_density,
        |accelerometer_random_walk, gyroscope_noise_density, gyroscope_random_walk, update_rate;
        |the largest axis, per-axis values in comments) and prints a table on standard error.
        |The four keys are continuous-time figures (kalibr's convention, independent of the rate);
        |comments give the discrete-time ones per sample at update_rate f: white noise
        |sigma_d = density * sqrt(f), bias random walk sigma_bd = random_walk / sqrt(f).
        |The app's still-recording mode makes such sessions ("still_recording": true in
        |meta.json); a session without that mark gets a note.
        |
        |Options:
        |  -o, --output FILE    write the YAML there instead of standard output
        |  --plot FILE          draw the curves with the fitted lines as SVG
        |  --configs DIR        also write the noise model for each VIO stack into DIR (new or empty),
        |                       each file with its conversion in its comments (docs/EXPORT.md):
        |                       imu.yaml (kalibr, as -o), kalibr_imu_chain.yaml (OpenVINS,
        |                       continuous), vins_imu.yaml (VINS-Mono/Fusion acc_n, gyr_n, acc_w,
        |                       gyr_w: per sample at the rate), orbslam3_imu.yaml (ORB-SLAM3
        |                       IMU.NoiseGyro ...: continuous, with IMU.Frequency)
        |  --quiet              no table on standard error
        |${InputOptions.HELP}
        |Exit codes: 0 ok, 1 malformed input or no gyroscope/accelerometer, 2 usage, 3 file not found/unwritable.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output", "--plot", "--configs") + InputOptions.VALUED, setOf("--quiet"))
        val input = o.positional.singleOrNull() ?: throw UsageException(if (o.positional.isEmpty()) "allan needs an INPUT" else "allan takes one INPUT")
        val output = o.value("-o") ?: o.value("--output")
        val plot = o.value("--plot")
        val configs = o.value("--configs")
        output?.let { outputs.requirePlainFile(it, "the noise model's YAML") }
        plot?.let { outputs.requirePlainFile(it, "the plot's SVG") }
        configs?.let { outputs.check(it, listOf(input)) }
        val outputTarget = output?.let { outputs.check(it, listOf(input)) }
        val plotTarget = plot?.let { outputs.check(it, listOf(input)) }
        // Real paths (links followed), so a link to the other output is the same file.
        if (outputTarget != null && plotTarget != null &&
            (outputTarget == plotTarget || (Files.exists(outputTarget) && Files.exists(plotTarget) && Files.isSameFile(outputTarget, plotTarget)))
        ) {
            throw UsageException("-o $output and --plot $plot name the same file")
        }
        val (result, name) = InputOptions.open(input, o, err, this.name).use { rec ->
            val meta = rec.metadata
            if (meta != null && !meta.stillRecording && !o.has("--quiet")) {
                err.println("fusion allan: note: ${rec.name} is not marked as a still recording (the app's still-recording mode): the figures hold only if the phone lay untouched throughout")
            }
            val progress = Progress(err, "allan", rec.metadata?.streams?.values?.sumOf { it.samples })
            val r = rec.events().use { e -> dev.motionfusion.core.calib.AllanResult.run(e, rec.streams, progress::update) }
            progress.finish()
            r to rec.name
        }
        val source = "fusion allan ${Cli.VERSION} from $name"
        NoiseModel.checkUsable(result, input)
        if (!o.has("--quiet")) err.print(AllanPlot.table(result))
        val yaml = result.kalibrYaml(source)
        // The files first, standard output last: a file that cannot be written leaves nothing half done on the terminal.
        if (configs != null) {
            val model = NoiseModel.parse(yaml, "the noise model of $input")
            val rate = model.rateHz ?: throw DataFormatException(input, 0, 0, "no sample rate for the noise configurations")
            val folder = outputs.folder(configs, listOf(input))
            for ((file, text) in NoiseConfigs.all(model, rate, source)) {
                Files.write(folder.resolve(file), text.toByteArray(StandardCharsets.UTF_8))
            }
        }
        if (plot != null) outputs.file(plot, listOf(input)).use { it.write(AllanPlot.svg(result, "Allan deviation of $name").toByteArray(StandardCharsets.UTF_8)) }
        if (output == null) out.print(yaml) else outputs.file(output, listOf(input)).use { it.write(yaml.toByteArray(StandardCharsets.UTF_8)) }
        return ExitCode.OK
    }

}
