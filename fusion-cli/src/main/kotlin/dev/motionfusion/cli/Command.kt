package dev.motionfusion.cli

import java.io.PrintStream

/** One subcommand of `fusion`. */
internal interface Command {
    /** The word after `fusion`. */
    val name: String

    /** One line for the command list. */
    val summary: String

    /** Full help text for `fusion NAME --help`. */
    val help: String

    /** Runs with the arguments after the name; returns an [ExitCode]. */
    fun run(args: List<String>, out: PrintStream): Int
}
