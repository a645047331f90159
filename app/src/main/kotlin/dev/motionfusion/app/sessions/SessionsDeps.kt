package dev.motionfusion.app.sessions

import kotlinx.coroutines.CoroutineDispatcher
import kotlinx.coroutines.Dispatchers

/** Seams for tests: where session files are read, and on which dispatcher. */
internal object SessionsDeps {
    @Volatile var library: SessionLibrary = CoreSessionLibrary
    @Volatile var io: CoroutineDispatcher = Dispatchers.IO

    fun reset() {
        library = CoreSessionLibrary
        io = Dispatchers.IO
    }
}
