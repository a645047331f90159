package dev.motionfusion.cli

import java.io.ByteArrayOutputStream
import java.io.PrintStream

/** What one in-process `fusion` run printed and returned. */
internal class CliResult(val code: Int, val out: String, val err: String)

/** Runs `fusion ARGS` in process, capturing standard output and error as UTF-8. */
internal fun fusion(vararg args: String): CliResult {
    val out = ByteArrayOutputStream()
    val err = ByteArrayOutputStream()
    val code = Cli(PrintStream(out, true, "UTF-8"), PrintStream(err, true, "UTF-8")).run(args.toList())
    return CliResult(code, out.toString("UTF-8"), err.toString("UTF-8"))
}
