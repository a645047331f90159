package dev.motionfusion.cli

import dev.motionfusion.core.session.SessionRecovery
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path

/** `fusion recover DIR`: repairs a session whose recording was interrupted. */
internal class RecoverCommand : Command {
    override val name = "recover"
    override val summary = "repair a session folder whose recording process was killed"
    override val help = """
        |Usage: fusion recover SESSION_DIR
        |
        |Cuts each stream file after its last complete line, recomputes the per-stream
        |statistics and rewrites meta.json with "complete": true and "recovered": true
        |(docs/SESSION_FORMAT.md, Recovery). A session that was closed normally is left alone.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, emptySet(), emptySet())
        val dir = o.positional.singleOrNull() ?: throw UsageException("recover needs one SESSION_DIR")
        val path = Path.of(dir)
        if (!Files.isDirectory(path)) throw UsageException("$dir is not a folder (unzip a session before recovering it)")
        val report = SessionRecovery.recover(path)
        if (report.truncatedBytes.isEmpty()) {
            out.println("$dir: complete session, nothing to do")
        } else {
            for ((s, n) in report.truncatedBytes) out.println("%-32s %d bytes cut".format(s.fileName, n))
            out.println("$dir: recovered; ${report.metadata.streams.values.sumOf { it.samples }} samples kept")
        }
        return ExitCode.OK
    }
}
