package dev.motionfusion.cli

import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.io.DataFormatException
import java.io.IOException
import java.io.PrintStream
import java.nio.file.FileSystemException
import java.nio.file.InvalidPathException
import java.util.Properties

/**
 * Dispatches `fusion` subcommands and turns failures into messages and [ExitCode]s. [out] is
 * checked after every run: a write that failed (closed pipe, full device) fails the run, and
 * [stdoutFailure] gives its reason when known. Files are written through [outputs].
 */
internal class Cli(
    private val out: PrintStream,
    private val err: PrintStream,
    private val outputs: Outputs = Outputs(),
    private val stdoutFailure: () -> IOException? = { null },
    /** `fusion replay`'s row time of a timestamp (one input of `replay --align`, run by [Batch]); null: its own origin. */
    private val rowTime: ((Long) -> Double)? = null,
) {
    constructor(out: PrintStream, err: PrintStream, stdoutFailure: () -> IOException?) : this(out, err, Outputs(), stdoutFailure)

    init {
        outputs.note = { err.println("fusion: note: $it") }
    }

    private val commands: List<Command> = listOf(
        ReplayCommand(err, outputs, rowTime), EvalCommand(err), CompareCommand(err, outputs), PlotCommand(err, outputs),
        SimulateCommand(outputs), RecoverCommand(), SummaryCommand(), CalibrateCommand(err, outputs), AllanCommand(err, outputs),
        ListenCommand(err), RecordCommand(err), ExportCommand(err, outputs), AlignCommand(err, outputs),
    )

    fun run(args: List<String>): Int {
        val code = dispatch(args)
        val stdoutFailed = out.checkError() // flushes
        if (code == ExitCode.OK && stdoutFailed) return fail(ExitCode.IO_ERROR, stdoutMessage())
        return code
    }

    private fun dispatch(args: List<String>): Int {
        val first = args.firstOrNull()
        return when {
            first == null || first == "--help" || first == "-h" || first == "help" -> {
                if (first == "help" && args.size > 1) return dispatch(listOf(args[1], "--help"))
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

    /** Runs [command]; its outputs are moved into place only when it succeeded and [out] took everything. */
    private fun execute(command: Command, args: List<String>): Int = try {
        val code = command.run(args, out)
        if (out.checkError()) throw StdoutException("write failed")
        if (code == ExitCode.OK) outputs.commit()
        code
    } catch (e: StdoutException) {
        fail(ExitCode.IO_ERROR, stdoutMessage())
    } catch (e: Throwable) {
        val (code, message) = failure(e, command.name, ::shown) ?: throw e
        fail(code, message)
    } finally {
        outputs.abort()
    }

    /** [file] as the user typed it (an output's real path maps back to its name), a very long one shortened. */
    private fun shown(file: String?): String {
        val f = file?.let { outputs.typed(it) } ?: return "?"
        return if (f.length <= MAX_SHOWN) f else "${f.take(MAX_SHOWN / 2)}…(${f.length} characters)…${f.takeLast(MAX_SHOWN / 4)}"
    }

    private fun stdoutMessage(): String =
        "standard output: ${stdoutFailure()?.let { AtomicFiles.reason(it) } ?: "write failed (closed pipe or full device)"}"

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
        appendLine("            ${ExitCode.USAGE} wrong command line (also: an output that names an input),")
        appendLine("            ${ExitCode.IO_ERROR} a file (or standard output) cannot be read or written, or out of memory;")
        appendLine("            the message names the file and the reason; ${ExitCode.CONNECTION_LOST} listen: the connection to the phone")
        appendLine("            was lost; ${ExitCode.DENIED} listen: denied on the phone; ${ExitCode.INTERNAL_ERROR} an internal error (a bug).")
        appendLine()
        appendLine("Outputs are written aside and moved into place only when the command succeeds: a failed")
        appendLine("run leaves an earlier file as it was. An output that is an input, or lies inside an input")
        appendLine("folder, is refused before anything is written.")
    }

    companion object {
        private const val MAX_SHOWN = 160

        /**
         * The exit code and message of a command's failure [e] (null: not one of the failures a
         * command reports, to be rethrown). [shown] gives a file as the user typed it. One mapping for
         * a whole run ([execute]) and for each input of a run over many ([Batch]).
         */
        fun failure(e: Throwable, command: String, shown: (String?) -> String = { it ?: "?" }): Pair<Int, String>? = when (e) {
            is UsageException -> ExitCode.USAGE to "${e.message}; run 'fusion $command --help'"
            is DataFormatException -> ExitCode.DATA_ERROR to (e.message ?: "malformed input")
            // Bytes of a name that are not valid in the system's encoding (e.g. 0xFF in UTF-8) reach Java as U+FFFD: no file has that name.
            is FileSystemException -> if (e.file?.contains('\uFFFD') == true && (e is java.nio.file.NoSuchFileException || e.reason == "no such file or folder")) {
                ExitCode.IO_ERROR to "${shown(e.file)}: the name holds bytes that are not ${System.getProperty("sun.jnu.encoding") ?: "in the system's file name encoding"} " +
                    "(shown as \uFFFD), which Java cannot pass on to the system: rename the file (a shell glob can name it)"
            } else {
                ExitCode.IO_ERROR to "${shown(e.file)}${e.otherFile?.let { " → ${shown(it)}" } ?: ""}: ${AtomicFiles.reason(e)}"
            }
            is IOException -> ExitCode.IO_ERROR to (e.message ?: e.toString())
            // e.g. a name with letters outside ASCII while LANG=C: Java cannot turn it into a path.
            is InvalidPathException -> ExitCode.USAGE to "'${e.input}': this file name cannot be represented in the system's file name encoding " +
                "(${System.getProperty("sun.jnu.encoding") ?: "unknown"}); run fusion in a UTF-8 locale, e.g. LC_ALL=C.UTF-8"
            is RuntimeException -> ExitCode.INTERNAL_ERROR to "internal error, a bug of fusion (please report it with the command line): $e"
            is OutOfMemoryError -> ExitCode.IO_ERROR to "out of memory: '$command' needs more than the ${Runtime.getRuntime().maxMemory() shr 20} MiB this Java may use; nothing was written. Give it more, e.g. FUSION_JAVA_OPTS=-Xmx4g"
            else -> null
        }

        val VERSION: String by lazy {
            Cli::class.java.getResourceAsStream("version.properties")?.use { s ->
                Properties().apply { load(s) }.getProperty("version")
            } ?: "unknown"
        }
    }
}
