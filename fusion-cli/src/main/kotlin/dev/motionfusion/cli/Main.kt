package dev.motionfusion.cli

import kotlin.system.exitProcess

/** Entry point of the `fusion` command. */
public fun main(args: Array<String>) {
    val code = Cli(System.out, System.err).run(args.toList())
    System.out.flush()
    exitProcess(code)
}
