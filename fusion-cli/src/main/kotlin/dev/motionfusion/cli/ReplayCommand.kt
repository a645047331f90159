package dev.motionfusion.cli

import dev.motionfusion.core.replay.ReplayCsvWriter
import dev.motionfusion.core.replay.Replayer
import java.io.BufferedOutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.util.zip.GZIPOutputStream

/** `fusion replay INPUT [-o OUT] [filter settings]`. */
internal class ReplayCommand(private val err: PrintStream) : Command {
    override val name = "replay"
    override val summary = "run the filter over a recording and write the orientation as CSV"
    override val help = """
        |Usage: fusion replay INPUT [-o OUT.csv[.gz]] [filter settings]
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
        |One input is one recording: a folder holding several is an error that lists them.
        |What an import assumed (a platform, a file left out) is printed as a note.
        |
        |Options:
        |  -o, --output FILE    write there (gzip if it ends in .gz) instead of standard output
        |  --quiet              no summary on standard error
        |${FilterOptions.HELP}
        |${InputOptions.HELP}
        |A progress bar is drawn on standard error when it is a terminal.
        |Exit codes: 0 ok, 1 malformed input (FILE:LINE:COLUMN: reason), 2 usage, 3 file not found/unwritable.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, setOf("-o", "--output") + FilterOptions.VALUED + InputOptions.VALUED, setOf("--quiet") + FilterOptions.FLAGS)
        val input = o.positional.singleOrNull() ?: throw UsageException(if (o.positional.isEmpty()) "replay needs an INPUT" else "replay takes one INPUT")
        val settings = FilterOptions.settings(o)
        val output = o.value("-o") ?: o.value("--output")
        InputOptions.open(input, o, err, name).use { rec ->
            val total = rec.metadata?.streams?.values?.sumOf { it.samples }
            val progress = Progress(err, "replay", total)
            val stream = if (output == null) StdoutGuard(out) else BufferedOutputStream(Files.newOutputStream(InputOptions.path(output)), 1 shl 16).let {
                if (output.endsWith(".gz")) GZIPOutputStream(it, 1 shl 16) else it
            }
            val writer = ReplayCsvWriter(stream, closeStream = output != null)
            val replayer = Replayer(settings)
            val counts = writer.use { w -> rec.events().use { e -> replayer.run(e, rec.originNs, w, progress::update) } }
            progress.finish()
            if (!o.has("--quiet")) {
                val d = replayer.filter.diagnostics()
                err.println(
                    "fusion replay: ${rec.format.description} ${rec.name}: ${counts.events} events, ${writer.rows} rows " +
                        "(${counts.gyroscope} gyroscope, ${counts.accelerometer} accelerometer, ${counts.magnetometer} magnetometer); " +
                        "skipped: ${d.skippedBeforeInit} before start, ${d.skippedTimestamp} bad timestamps, ${d.skippedGap} after gaps",
                )
            }
            if (counts.gyroscope == 0L) {
                err.println("fusion replay: ${rec.name} has no gyroscope samples: nothing to replay")
                return ExitCode.DATA_ERROR
            }
        }
        return ExitCode.OK
    }
}

/**
 * Standard output that stops the run once it is closed (e.g. `fusion replay … | head`):
 * PrintStream swallows write errors, which would let a long replay run on for nothing.
 */
internal class StdoutGuard(private val out: PrintStream) : java.io.OutputStream() {
    override fun write(b: Int) = write(byteArrayOf(b.toByte()), 0, 1)

    override fun write(b: ByteArray, off: Int, len: Int) {
        out.write(b, off, len)
        if (out.checkError()) throw java.io.IOException("standard output closed")
    }

    override fun flush() {
        out.flush()
        if (out.checkError()) throw java.io.IOException("standard output closed")
    }
}
