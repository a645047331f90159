package dev.motionfusion.cli

import dev.motionfusion.core.io.DataFormatException
import java.io.IOException
import java.io.PrintStream
import java.nio.file.NoSuchFileException
import java.util.Properties

/** Dispatches `fusion` subcommands and turns failures into messages and [ExitCode]s. */
internal class Cli(private val out: PrintStream, private val err: PrintStream) {

    private val commands: List<Command> = listOf(
        ReplayCommand(err), EvalCommand(err), CompareCommand(err), PlotCommand(err),
        SimulateCommand(), RecoverCommand(), SummaryCommand(), CalibrateCommand(err), AllanCommand(err),
    )

    fun run(args: List<String>): Int {
        val first = args.firstOrNull()
        return when {
            first == null || first == "--help" || first == "-h" || first == "help" -> {
                if (first == "help" && args.size > 1) return run(listOf(args[1], "--help"))
                out.print(usage())
                if (first == null) ExitCode.USAGE else ExitCode.OK
            }
            first == "--version" || first == "-V" -> {
                out.println("fusion $VERSION")
                ExitCode.OK
            }
            else -> {
                val command = commands.firstOrNull { it.name == first }
                    ?: return fail(ExitCode.USAGE, "unknown command '$first'; run 'fusion --help' for the list")
                val rest = args.drop(1)
                if ("--help" in rest || "-h" in rest) {
                    out.print(command.help)
                    ExitCode.OK
                } else {
                    execute(command, rest)
                }
            }
        }
    }

    private fun execute(command: Command, args: List<String>): Int = try {
        command.run(args, out)
    } catch (e: UsageException) {
        fail(ExitCode.USAGE, "${e.message}; run 'fusion ${command.name} --help'")
    } catch (e: DataFormatException) {
        fail(ExitCode.DATA_ERROR, e.message ?: "malformed input")
    } catch (e: NoSuchFileException) {
        fail(ExitCode.IO_ERROR, "${e.file}: no such file")
    } catch (e: IOException) {
        fail(ExitCode.IO_ERROR, e.message ?: e.toString())
    }

    private fun fail(code: Int, message: String): Int {
        err.println("fusion: $message")
        return code
    }

    private fun usage(): String = buildString {
        appendLine("fusion $VERSION: orientation from phone IMU recordings with the Madgwick filter")
        appendLine()
        appendLine("Usage: fusion COMMAND [ARGS...]      fusion COMMAND --help for details")
        appendLine()
        appendLine("Commands:")
        for (c in commands) appendLine("  %-10s %s".format(c.name, c.summary))
        appendLine()
        appendLine("Options: --help, --version")
        appendLine()
        appendLine("Exit codes: ${ExitCode.OK} success, ${ExitCode.DATA_ERROR} malformed input (file:line:column given),")
        appendLine("            ${ExitCode.USAGE} wrong command line, ${ExitCode.IO_ERROR} file not found or not readable/writable")
    }

    companion object {
        val VERSION: String by lazy {
            Cli::class.java.getResourceAsStream("version.properties")?.use { s ->
                Properties().apply { load(s) }.getProperty("version")
            } ?: "unknown"
        }
    }
}
