package dev.motionfusion.app.sessions

import kotlinx.coroutines.CoroutineDispatcher

/** What the sessions screens need, from the application's object graph. */
internal interface SessionsDependencies {
    val sessions: SessionsRepository
    val library: SessionLibrary

    /** The disk executor as a dispatcher: every read, repair, export, rename and delete runs there. */
    val io: CoroutineDispatcher

    /** Implemented by the application. */
    interface Provider {
        val sessionsDependencies: SessionsDependencies
    }
}
