package dev.motionfusion.app.stream

import androidx.annotation.StringRes
import dev.motionfusion.app.R
import java.net.BindException
import java.net.UnknownHostException
import java.nio.channels.UnresolvedAddressException

/**
 * What kind of failure the live stream met, in the user's words: [text] is a string resource in every
 * language the app ships, saying what failed and what to do. The exception or the stream library's reason
 * (English, the system's words) goes to the log only ([StreamController]'s log).
 */
internal enum class StreamFailure(@StringRes val text: Int) {
    /** Another app listens on the stream's port. */
    PORT_IN_USE(R.string.stream_failure_port_in_use),

    /** The server could not listen, or the UDP push could not open its socket. */
    NETWORK(R.string.stream_failure_network),

    /** The server stopped by itself while on (the stream library's fatal error, such as running out of memory). */
    SERVER_STOPPED(R.string.stream_failure_server_stopped),

    /** The UDP push's host name is not known on the network. */
    HOST_UNKNOWN(R.string.stream_failure_host_unknown),

    /** The UDP push's address is outside the local network. */
    NOT_LOCAL(R.string.stream_failure_not_local),
    ;

    companion object {
        /** The kind of [e], met while starting the server or the UDP push. */
        fun of(e: Throwable): StreamFailure {
            val chain = generateSequence(e) { it.cause }.take(8).toList()
            return when {
                chain.any { it is BindException } -> PORT_IN_USE
                chain.any { it is UnknownHostException || it is UnresolvedAddressException } -> HOST_UNKNOWN
                else -> NETWORK
            }
        }
    }
}
