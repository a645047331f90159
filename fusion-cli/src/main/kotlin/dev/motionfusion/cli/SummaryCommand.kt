package dev.motionfusion.cli

import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.io.ImuTableReader
import java.io.PrintStream
import java.nio.file.Path

/** `fusion summary FILE`: counts, duration, rate and per-axis means of a plain IMU table. */
internal class SummaryCommand : Command {
    override val name = "summary"
    override val summary = "samples, duration, rate and per-axis means of an IMU table"
    override val help = """
        |Usage: fusion summary FILE
        |
        |Reads a plain IMU table (CSV, optionally gzip-compressed) with the header
        |  t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]
        |(s, rad/s, m/s², µT; device frame) and prints the number of samples, the
        |duration, the sample rate, timestamp problems and the mean of every axis.
        |Malformed input stops with FILE:LINE:COLUMN and the reason (exit code 1).
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val file = args.singleOrNull() ?: throw UsageException(
            if (args.isEmpty()) "summary needs a FILE" else "summary takes one FILE, got ${args.size} arguments",
        )
        if (file.startsWith("-")) throw UsageException("unknown option '$file'")
        val stats = try {
            ImuTableReader.open(Path.of(file)).use { reader ->
                TableStats(reader.hasMagnetometer).also { s -> reader.forEach(s::add) }
            }
        } catch (e: java.util.zip.ZipException) {
            throw DataFormatException(file, 0, 0, "corrupt gzip data: ${e.message}")
        } catch (e: java.io.EOFException) {
            throw DataFormatException(file, 0, 0, "gzip data ends early")
        }
        out.print(stats.report(file))
        return ExitCode.OK
    }
}
