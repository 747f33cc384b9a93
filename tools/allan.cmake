# legkit allan. Owner: allan.
