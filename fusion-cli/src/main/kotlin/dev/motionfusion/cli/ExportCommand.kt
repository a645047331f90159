package dev.motionfusion.cli

import dev.motionfusion.core.export.ExportFormat
import dev.motionfusion.core.export.ExportOptions
import dev.motionfusion.core.export.Exports
import dev.motionfusion.core.export.NoiseModel
import dev.motionfusion.core.io.DataFormatException
import java.io.PrintStream
import java.nio.file.Path

/**
 * `fusion export INPUT --format euroc|kalibr|gcsv|ros2 -o OUT`: a recording in the layout another tool
 * reads (docs/EXPORT.md), written by fusion-core's [Exports] (the app's Share/Save writes the same).
 */
internal class ExportCommand(private val err: PrintStream, private val outputs: Outputs) : Command {
    override val name = "export"
    override val summary = "write a recording as EuRoC (ASL), Kalibr, Gyroflow gcsv or ROS 2 MCAP for other tools"
    override val help = """
        |Usage: fusion export INPUT --format euroc|kalibr|gcsv|ros2 -o OUT [options] [filter settings]
        |
        |Writes the recording (any input of fusion replay) in a layout other tools read; the
        |details, frames and checks are in docs/EXPORT.md:
        |  euroc    OUT/ as an EuRoC (ASL) folder: mav0/imu0/data.csv and sensor.yaml (gyroscope
        |           rad/s, accelerometer m/s²), mav0/mag0/data.csv (magnetometer µT, each reading at
        |           its own time), mav0/state_groundtruth_estimate0/data.csv: the fused orientation
        |           of the replay (an estimate, not ground truth; EuRoC's 17 columns, position,
        |           velocity and biases 0)
        |  kalibr   OUT/ holding imu0.csv (timestamp,omega_x,…,alpha_z) and imu.yaml, as
        |           kalibr_bagcreater and kalibr read them
        |  gcsv     OUT as a Gyroflow gcsv 1.3 log (gyroscope, accelerometer, magnetometer)
        |  ros2     OUT as a ROS 2 MCAP file (CDR): sensor_msgs/msg/Imu on /imu/data_raw (no
        |           orientation) and /imu/data (the replay's orientation), MagneticField on /imu/mag
        |           (tesla), frame_id imu_link; covariances as REP-145 says: angular velocity and linear
        |           acceleration from --noise (N²·f on the diagonal), else unknown (0)
        |Rows: one per gyroscope sample from the first accelerometer reading on (for gcsv with a
        |magnetometer: from the first of both), the other sensors held at its instant. Times: the
        |recording's own clock, ns (gcsv: tscale 1e-9), moved later by whole seconds when it starts
        |before 0 (a note says so). Frame: Android device axes (x right, y up, z out of the
        |screen); orientation [w, x, y, z] sensor → ENU, Hamilton. Filter and heading options with
        |kalibr or gcsv (no orientation in either), and --noise with gcsv, are usage errors.
        |
        |Options:
        |  --format F           euroc, kalibr, gcsv or ros2 (required)
        |  -o, --output OUT     the folder (euroc, kalibr; must not exist or be empty) or file (gcsv, ros2)
        |  --noise FILE         the phone's noise model: an imu.yaml of fusion allan (kalibr's keys);
        |                       its four figures go into EuRoC's sensor.yaml, the file itself becomes
        |                       Kalibr's imu.yaml, and ROS 2's angular velocity and linear
        |                       acceleration covariances are N²·f (f: the gyroscope's mean rate).
        |                       Without it no noise figure is written (a comment says so)
        |  --calibration FILE|recorded|none   as in fusion replay (default: as the live filter did)
        |  --quiet              no summary and no notes on standard error (warnings and errors still)
        |${HeadingOptions.HELP}
        |${FilterOptions.HELP}
        |${InputOptions.HELP}
        |The output is written aside and moved into place only when the export succeeds; an
        |output that is an input or lies inside one is refused before anything is written.
        |Exit codes: 0 ok, 1 malformed input (FILE:LINE:COLUMN: reason), 2 usage, 3 file not found/unwritable.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val valued = setOf("-o", "--output", "--format", "--noise", "--calibration") + FilterOptions.VALUED + InputOptions.VALUED + HeadingOptions.VALUED
        val o = Options(args, valued, setOf("--quiet") + FilterOptions.FLAGS)
        val input = o.positional.singleOrNull() ?: throw UsageException(if (o.positional.isEmpty()) "export needs an INPUT" else "export takes one INPUT")
        val format = when (val f = o.value("--format")?.lowercase()) {
            null -> throw UsageException("export needs --format euroc, kalibr, gcsv or ros2")
            else -> ExportFormat.of(f) ?: throw UsageException("--format expects euroc, kalibr, gcsv or ros2, got '$f'")
        }
        val output = o.value("-o") ?: o.value("--output") ?: throw UsageException("export needs -o OUT")
        if (!format.folder) outputs.requirePlainFile(output, "a ${format.key} export")
        // Options with nothing to act on in this format are refused, not ignored: kalibr and gcsv hold no orientation.
        if (format == ExportFormat.KALIBR || format == ExportFormat.GCSV) {
            val given = (FilterOptions.VALUED + HeadingOptions.VALUED).filter { o.value(it) != null || o.values(it).isNotEmpty() } + FilterOptions.FLAGS.filter { o.has(it) }
            if (given.isNotEmpty()) {
                throw UsageException("${given.joinToString(", ")}: a ${format.key} export holds no orientation, so filter and heading options have nothing to act on")
            }
        }
        if (format == ExportFormat.GCSV && o.value("--noise") != null) {
            throw UsageException("--noise: a gcsv export has no place for a noise model (euroc, kalibr and ros2 have)")
        }
        FilterOptions.settings(o) // usage errors before the input is opened
        val offline = FilterOptions.offline(o)
        val heading = HeadingOptions.spec(o)
        val noiseFile = o.value("--noise")
        val inputs = listOfNotNull(input, noiseFile, o.value("--calibration")?.takeUnless { it == "recorded" || it == "none" })
        outputs.check(output, inputs)
        val noise = noiseFile?.let { NoiseModel.read(Path.of(it)) }
        val file = ReplayCommand.calibrationFile(o)
        InputOptions.open(input, o, err, name).use { rec ->
            val settings = FilterOptions.settings(o, rec, err, name)
            val calibration = ReplayCommand.calibration(o, file, rec, err, name)
            val options = ExportOptions(settings, calibration, offline, noise, heading, "fusion export ${Cli.VERSION}")
            val progress = Progress(err, name, rec.metadata?.streams?.values?.sumOf { it.samples })
            val result = try {
                if (format.folder) Exports.writeFolder(rec, format, outputs.folder(output, inputs), options, progress::update)
                else Exports.writeFile(rec, format, outputs.file(output, inputs), options, progress::update)
            } catch (e: DataFormatException) {
                // Nothing to export: said as before, without a file position.
                if (e.line == 0L && e.reason.endsWith("nothing to export")) {
                    progress.finish()
                    err.println("fusion export: ${rec.name} has ${e.reason}")
                    return ExitCode.DATA_ERROR
                }
                throw e
            }
            progress.finish()
            if (!o.has("--quiet")) {
                val counts = result.counts
                val withMore = format == ExportFormat.EUROC || format == ExportFormat.ROS2
                err.println(
                    "fusion export: ${rec.format.description} ${rec.name} → ${format.key} $output: ${result.imuRows} IMU rows" +
                        (if (withMore) ", ${result.orientationRows} orientation rows" else "") +
                        (if (withMore && rec.hasMagnetometer) ", ${result.magnetometerRows} magnetometer rows" else "") +
                        " (${counts.gyroscope} gyroscope, ${counts.accelerometer} accelerometer, ${counts.magnetometer} magnetometer samples read)",
                )
            }
            if (result.clockShiftNs != 0L) {
                err.println("fusion export: note: ${rec.name} starts before t = 0; every time written is ${result.clockShiftNs / 1_000_000_000L} s later than the recording's (the formats' times are never negative; the files say so)")
            }
        }
        return ExitCode.OK
    }
}
