package dev.motionfusion.cli

import dev.motionfusion.core.input.ImuTableReader
import dev.motionfusion.core.io.DataFormatException
import java.io.PrintStream

/** `fusion summary FILE`: counts, duration, rate and per-axis means of a plain IMU table. */
internal class SummaryCommand : Command {
    override val name = "summary"
    override val summary = "samples, duration, rate and per-axis means of an IMU table"
    override val help = """
        |Usage: fusion summary FILE
        |
        |Reads a plain IMU table (CSV, optionally gzip-compressed; - for standard input) with the header
        |  t_s,gx,gy,gz,ax,ay,az[,mx,my,mz]
        |(s, rad/s, m/s², µT; device frame) and prints the number of samples, the
        |duration, the sample rate (gaps, an interval over five times the mean, left out and
        |counted), timestamp problems and the mean of every axis.
        |Malformed input stops with FILE:LINE:COLUMN and the reason (exit code 1).
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        // Options first: summary has none, so "summary FILE --quiet" is an unknown option, not a second FILE.
        args.firstOrNull { it.startsWith("-") && it != "-" }?.let { throw UsageException("unknown option '$it'") }
        val file = args.singleOrNull() ?: throw UsageException(
            if (args.isEmpty()) "summary needs a FILE" else "summary takes one FILE, got ${args.size} arguments",
        )
        val stats = ImuTableReader.open(InputOptions.path(file)).use { reader ->
            TableStats(reader.hasMagnetometer).also { s -> while (reader.next()) s.add(reader.timeS, reader.row) }
        }
        if (stats.samples == 0L) throw DataFormatException(file, 0, 0, "no rows after the header: nothing to summarise")
        out.print(stats.report(file))
        return ExitCode.OK
    }
}
