package dev.motionfusion.cli

import dev.motionfusion.core.io.AtomicFiles
import dev.motionfusion.core.session.SessionRecovery
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.attribute.BasicFileAttributes
import java.nio.file.Path

/** `fusion recover [--dry-run] DIR`: repairs a session whose recording was interrupted. */
internal class RecoverCommand : Command {
    override val name = "recover"
    override val summary = "repair a session folder whose recording process was killed"
    override val help = """
        |Usage: fusion recover [--dry-run] SESSION_DIR
        |
        |Cuts each stream file after its last complete line, recomputes the per-stream
        |statistics and replaces meta.json with "complete": true and "recovered": true
        |(docs/SESSION_FORMAT.md, Recovery). A session that was closed normally is left alone.
        |
        |It cannot do harm: it acts only on a folder whose meta.json says
        |"format": "motion-fusion-session" (or, when meta.json is missing or cut short, on a
        |folder holding nothing but session files: meta.json is rebuilt from the streams and the
        |unreadable one kept as meta.json.unreadable); it reads and checks every stream before it
        |changes any; it never follows a symbolic link nor touches another file; it keeps every
        |meta.json member it does not know; meta.json is replaced atomically, last, so a kill or a
        |full disk at any step leaves a session that can be recovered again.
        |
        |Options:
        |  --dry-run            say what would be done; change nothing
        |Exit codes: 0 done (or nothing to do), 1 not a session of this project, a link, or a
        |malformed row (FILE:LINE:COLUMN; nothing changed), 2 usage, 3 unreadable/unwritable file.
        |""".trimMargin()

    override fun run(args: List<String>, out: PrintStream): Int {
        val o = Options(args, emptySet(), setOf("--dry-run"))
        val dir = o.positional.singleOrNull() ?: throw UsageException("recover needs one SESSION_DIR")
        val path = Path.of(dir)
        val kind = AtomicFiles.named(path) { Files.readAttributes(path, BasicFileAttributes::class.java) }
        if (!kind.isDirectory) throw UsageException("$dir is not a folder (unzip a session before recovering it)")
        val dryRun = o.has("--dry-run")
        val report = SessionRecovery().recover(path, dryRun)
        if (report.wasComplete) {
            out.println("$dir: complete session, nothing to do")
        } else {
            for (a in report.actions) out.println((if (dryRun) "would: " else "") + a)
            val samples = report.metadata.streams.values.sumOf { it.samples }
            out.println(if (dryRun) "$dir: dry run, nothing changed; $samples samples would be kept" else "$dir: recovered; $samples samples kept")
        }
        return ExitCode.OK
    }
}
