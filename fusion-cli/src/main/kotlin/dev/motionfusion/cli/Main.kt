package dev.motionfusion.cli

import java.io.FileDescriptor
import java.io.FileOutputStream
import java.io.PrintStream
import kotlin.system.exitProcess

/** Entry point of the `fusion` command. */
public fun main(args: Array<String>) {
    // Temporary names carry the process id, so that a later run tells a killed run's leftovers from a running one's files.
    dev.motionfusion.core.io.TemporaryFiles.owner = ProcessHandle.current().pid().toString()
    val stdout = RecordingOutput(FileOutputStream(FileDescriptor.out))
    val out = PrintStream(java.io.BufferedOutputStream(stdout, 1 shl 16), false, System.getProperty("sun.stdout.encoding") ?: java.nio.charset.Charset.defaultCharset().name())
    val code = Cli(out, System.err, stdoutFailure = { stdout.failure }).run(args.toList())
    exitProcess(code)
}
