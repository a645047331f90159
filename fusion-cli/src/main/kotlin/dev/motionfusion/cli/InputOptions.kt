package dev.motionfusion.cli

import dev.motionfusion.core.input.ImportOptions
import dev.motionfusion.core.input.Platform
import dev.motionfusion.core.input.Recording
import dev.motionfusion.core.io.InputLimits
import java.io.PrintStream
import java.nio.file.Path
import java.nio.file.Paths

/** The input options shared by every command that reads recordings, and the one way they open an input. */
internal object InputOptions {
    val VALUED = setOf("--platform", "--max-uncompressed")

    val HELP = """
        |Input options:
        |  --platform android|ios   the phone of a Sensor Logger export whose Metadata.csv does not say
        |                       (iOS exports have the opposite acceleration sign); default: inferred, else android
        |  --max-uncompressed SIZE  largest decompressed size of one compressed file (.gz, zip entry), e.g. 40G;
        |                       four times that in total (default 16G, a day of recording)
        |""".trimMargin()

    fun limits(o: Options): InputLimits {
        val v = o.value("--max-uncompressed") ?: return InputLimits()
        val m = Regex("""^(\d+)([kKmMgGtT]?)[bB]?$""").matchEntire(v) ?: throw UsageException("--max-uncompressed expects a size like 500M or 40G, got '$v'")
        val shift = when (m.groupValues[2].lowercase()) { "k" -> 10; "m" -> 20; "g" -> 30; "t" -> 40; else -> 0 }
        val n = m.groupValues[1].toLongOrNull()?.takeIf { it > 0 && it <= (Long.MAX_VALUE shr shift) } ?: throw UsageException("--max-uncompressed: '$v' is out of range")
        return InputLimits.perFile(n shl shift)
    }

    fun options(o: Options): ImportOptions {
        val platform = when (o.value("--platform")?.lowercase()) {
            null -> null
            "android" -> Platform.ANDROID
            "ios" -> Platform.IOS
            else -> throw UsageException("--platform expects android or ios")
        }
        return ImportOptions(limits(o), platform)
    }

    /** Opens [input] with the options of [o]; what the import assumed goes to [err] as notes (none with --quiet). */
    fun open(input: String, o: Options, err: PrintStream, command: String): Recording {
        val quiet = o.has("--quiet")
        val path = Paths.get(input)
        if (input == "-" || (java.nio.file.Files.exists(path) && !java.nio.file.Files.isRegularFile(path) && !java.nio.file.Files.isDirectory(path))) {
            // Read once into the temporary folder: first remove what a killed earlier run left there.
            val started = java.lang.management.ManagementFactory.getRuntimeMXBean().startTime
            val removed = dev.motionfusion.core.io.TemporaryFiles.removeStaleInputs(started, Outputs::alive)
            if (removed.isNotEmpty() && !quiet) err.println("fusion $command: note: removed ${removed.size} spooled input${if (removed.size == 1) "" else "s"} an interrupted earlier run left: ${removed.joinToString(", ")}")
        }
        val rec = Recording.open(path, options(o))
        if (!quiet) for (n in rec.notes) err.println("fusion $command: note: ${rec.name}: $n")
        if (o.value("--platform") != null && rec.format != dev.motionfusion.core.input.RecordingFormat.SENSOR_LOGGER) {
            err.println("fusion $command: note: ${rec.name}: --platform is for Sensor Logger exports; a ${rec.format.description} says its own axes, so it is not used")
        }
        return rec
    }

    fun path(p: String): Path = Paths.get(p)
}
